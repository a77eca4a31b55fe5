/* What the physics-only baselines (bare_mj_step.c, paced_mj_step.c) share: the clock they time
 * with, and the model with the controls file it replays (little-endian doubles, written by
 * baselines.py: nq initial qpos, then for every tick nu ctrl followed by nv qfrc_applied). Included
 * once by each program, after <mujoco/mujoco.h>; the includer defines _POSIX_C_SOURCE for
 * clock_gettime. */
#ifndef CRSLAB_BENCH_CONTROLS_FILE_H
#define CRSLAB_BENCH_CONTROLS_FILE_H

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

/* seconds on `clock` (CLOCK_MONOTONIC, CLOCK_PROCESS_CPUTIME_ID) */
static double clock_s(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The whole file as doubles (*count of them), malloc'ed; NULL when it cannot be read. */
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

/* MODEL.xml and the controls file recorded on it: the model, with the recording in *rec and its
 * tick count in *ticks (at least one); NULL, said on stderr, when either cannot be read or they do
 * not fit each other. */
static mjModel *load_replay(const char *model_xml, const char *controls, double **rec, long *ticks)
{
    char error[1000] = "";
    mjModel *m = mj_loadXML(model_xml, NULL, error, sizeof error);
    if (!m) {
        fprintf(stderr, "%s: %s\n", model_xml, error);
        return NULL;
    }
    long count = 0;
    *rec = read_doubles(controls, &count);
    /* (sizes are int in MuJoCo 3, mjtSize in 4: use long here) */
    const long nq = (long)m->nq, nu = (long)m->nu, nv = (long)m->nv, per_tick = nu + nv;
    if (!*rec || count <= nq || (count - nq) % per_tick != 0) {
        fprintf(stderr, "%s: not a controls file for this model (nq %ld, nu %ld, nv %ld)\n", controls, nq,
                nu, nv);
        free(*rec);
        *rec = NULL;
        mj_deleteModel(m);
        return NULL;
    }
    *ticks = (count - nq) / per_tick;
    return m;
}

#endif
