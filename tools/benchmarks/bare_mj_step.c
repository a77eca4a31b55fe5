/* The bare physics loop crslab's simulator is measured against (tools/benchmarks/bench_sim.py).
 *
 * Loads MODEL.xml with the MuJoCo library the `mujoco` Python package ships (the one crslab's
 * worker calls), puts the arm in the recorded initial pose, runs mj_forward, then times a plain
 * loop of mj_step, one per recorded tick, that copies the tick's recorded controls (ctrl) and
 * applied joint forces (qfrc_applied) into mjData before stepping: the same physics as the
 * crslab run they were recorded from, with nothing else done per step.
 *
 *   bare_mj_step MODEL.xml CONTROLS.bin PASSES
 *
 * CONTROLS.bin holds little-endian doubles: nq initial qpos, then for every tick nu ctrl
 * followed by nv qfrc_applied (tools/benchmarks/baselines.py writes it). Every pass starts from
 * the same state. Prints one line "pass SECONDS STEPS CPU_SECONDS" per pass (wall time, steps,
 * this process's CPU time), then "qpos ..." and "qvel ..." of the final state (%.17g, so the
 * caller can check it bit for bit).
 */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#include <mujoco/mujoco.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "controls_file.h"

static void print_vector(const char *name, const mjtNum *v, long n)
{
    printf("%s", name);
    for (long i = 0; i < n; ++i) printf(" %.17g", v[i]);
    printf("\n");
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: %s MODEL.xml CONTROLS.bin PASSES\n", argv[0]);
        return 2;
    }
    double *rec = NULL;
    long ticks = 0;
    mjModel *m = load_replay(argv[1], argv[2], &rec, &ticks);
    if (!m) return 2;
    const long nq = (long)m->nq, nu = (long)m->nu, nv = (long)m->nv, per_tick = nu + nv;
    const int passes = atoi(argv[3]);
    mjData *d = mj_makeData(m);
    for (int pass = 0; pass < passes; ++pass) {
        mj_resetData(m, d);
        memcpy(d->qpos, rec, sizeof(mjtNum) * (size_t)nq);
        mj_forward(m, d);
        const double *tick = rec + nq;
        const double start = clock_s(CLOCK_MONOTONIC), start_cpu = clock_s(CLOCK_PROCESS_CPUTIME_ID);
        for (long k = 0; k < ticks; ++k, tick += per_tick) {
            memcpy(d->ctrl, tick, sizeof(mjtNum) * (size_t)nu);
            memcpy(d->qfrc_applied, tick + nu, sizeof(mjtNum) * (size_t)nv);
            mj_step(m, d);
        }
        const double wall = clock_s(CLOCK_MONOTONIC) - start;
        printf("pass %.9f %ld %.9f\n", wall, ticks, clock_s(CLOCK_PROCESS_CPUTIME_ID) - start_cpu);
    }
    print_vector("qpos", d->qpos, nq);
    print_vector("qvel", d->qvel, nv);
    mj_deleteData(d);
    mj_deleteModel(m);
    free(rec);
    return 0;
}
