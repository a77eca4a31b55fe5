/* MuJoCo's step alone, paced as a run host paces its runs (tools/benchmarks/bench_serve.py).
 *
 * The bare loop (bare_mj_step.c) steps one run without a pause: the core never idles. A run host
 * steps its worker's runs at real time: 250-tick chunks, a wake-up every 60 ms running every chunk
 * due within it, the core idle in between. This program does the same physics at the same pace
 * with nothing else (CHUNK_TICKS and BATCH_MS given by the caller from crslab's own pacing
 * constants): RUNS runs of MODEL.xml (one model, a data each, as a worker shares its model),
 * each replaying CONTROLS.bin (bare_mj_step.c's format) from its own place in it, each at real
 * time from its own phase of the chunk period, for SECONDS of wall time. On a machine whose idle
 * cores run slower once they wake (a virtual machine's), the step paced costs more CPU than the
 * step in a loop: what crslab's server pays for pacing whatever it adds itself.
 *
 *   paced_mj_step MODEL.xml CONTROLS.bin RUNS SECONDS CHUNK_TICKS BATCH_MS
 *
 * Prints "paced STEPS CPU_SECONDS WAKEUPS" (steps taken, this process's CPU time while stepping,
 * wake-ups), then "qpos ..." of the first run (%.17g, which starts at the recording's first tick:
 * the caller can check that it did the recording's physics).
 */
#define _POSIX_C_SOURCE 200112L /* clock_nanosleep */
#include <mujoco/mujoco.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "controls_file.h"

static const double GOLDEN = 0.6180339887498949; /* runs' phases: the host's golden-ratio spread */

static void sleep_until(double when_s)
{
    struct timespec ts;
    ts.tv_sec = (time_t)when_s;
    ts.tv_nsec = (long)((when_s - (double)ts.tv_sec) * 1e9);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) != 0) {
    }
}

int main(int argc, char **argv)
{
    if (argc != 7) {
        fprintf(stderr, "usage: %s MODEL.xml CONTROLS.bin RUNS SECONDS CHUNK_TICKS BATCH_MS\n", argv[0]);
        return 2;
    }
    double *rec = NULL;
    long ticks = 0;
    mjModel *m = load_replay(argv[1], argv[2], &rec, &ticks);
    if (!m) return 2;
    const long nq = (long)m->nq, nu = (long)m->nu, nv = (long)m->nv, per_tick = nu + nv;
    const int runs = atoi(argv[3]);
    const double seconds = atof(argv[4]);
    const int chunk_ticks = atoi(argv[5]);         /* a chunk at real time (ticks of 1 ms) */
    const double batch_s = atof(argv[6]) * 1e-3;    /* a wake-up runs every chunk due this soon */
    if (runs < 1 || !(seconds > 0) || chunk_ticks < 1 || !(batch_s > 0)) {
        fprintf(stderr, "RUNS, SECONDS, CHUNK_TICKS and BATCH_MS must be positive\n");
        return 2;
    }
    mjData **data = malloc(sizeof *data * (size_t)runs);
    long *at = calloc((size_t)runs, sizeof *at);      /* each run's tick in the recording */
    double *due = malloc(sizeof *due * (size_t)runs); /* when each run's next chunk is due (s) */
    if (!data || !at || !due) return 2;
    const double period_s = chunk_ticks * 1e-3, start = clock_s(CLOCK_MONOTONIC) + batch_s;
    for (int r = 0; r < runs; ++r) {
        data[r] = mj_makeData(m);
        memcpy(data[r]->qpos, rec, sizeof(mjtNum) * (size_t)nq);
        mj_forward(m, data[r]);
        at[r] = (long)r * 997 % ticks;
        due[r] = start + fmod(r * GOLDEN, 1.0) * period_s;
    }
    long steps = 0, wakeups = 0;
    double cpu_s = 0.0;
    for (double wake = start; wake < start + seconds; wake += batch_s) {
        sleep_until(wake);
        const double cpu0 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
        for (int r = 0; r < runs; ++r) {
            for (; due[r] < wake + batch_s; due[r] += period_s) {
                mjData *d = data[r];
                for (int k = 0; k < chunk_ticks; ++k, ++steps) {
                    const double *tick = rec + nq + at[r] * per_tick;
                    memcpy(d->ctrl, tick, sizeof(mjtNum) * (size_t)nu);
                    memcpy(d->qfrc_applied, tick + nu, sizeof(mjtNum) * (size_t)nv);
                    mj_step(m, d);
                    if (++at[r] == ticks) { /* the recording's end: that run starts it again */
                        at[r] = 0;
                        mj_resetData(m, d);
                        memcpy(d->qpos, rec, sizeof(mjtNum) * (size_t)nq);
                        mj_forward(m, d);
                    }
                }
            }
        }
        cpu_s += clock_s(CLOCK_PROCESS_CPUTIME_ID) - cpu0;
        ++wakeups;
    }
    printf("paced %ld %.9f %ld\nqpos", steps, cpu_s, wakeups);
    for (long i = 0; i < nq; ++i) printf(" %.17g", data[0]->qpos[i]);
    printf("\n");
    for (int r = 0; r < runs; ++r) mj_deleteData(data[r]);
    free(data);
    free(at);
    free(due);
    mj_deleteModel(m);
    free(rec);
    return 0;
}
