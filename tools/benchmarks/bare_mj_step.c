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

static double clock_s(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double *read_doubles(const char *path, long *count)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    const long bytes = ftell(f);
    fseek(f, 0, SEEK_SET);
    double *values = malloc(bytes > 0 ? (size_t)bytes : 1);
    *count = bytes / (long)sizeof(double);
    if (values && fread(values, sizeof(double), (size_t)*count, f) != (size_t)*count) {
        free(values);
        values = NULL;
    }
    fclose(f);
    return values;
}

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
    char error[1000] = "";
    mjModel *m = mj_loadXML(argv[1], NULL, error, sizeof error);
    if (!m) {
        fprintf(stderr, "%s: %s\n", argv[1], error);
        return 2;
    }
    long count = 0;
    double *rec = read_doubles(argv[2], &count);
    /* (sizes are int in MuJoCo 3, mjtSize in 4: use long here) */
    const long nq = (long)m->nq, nu = (long)m->nu, nv = (long)m->nv, per_tick = nu + nv;
    if (!rec || count < nq || (count - nq) % per_tick != 0) {
        fprintf(stderr, "%s: not a controls file for this model (nq %ld, nu %ld, nv %ld)\n", argv[2],
                nq, nu, nv);
        return 2;
    }
    const long ticks = (count - nq) / per_tick;
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
