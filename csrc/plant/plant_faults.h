/* Faults a scenario injects on the plant's hardware (crs_faults; crslab/scenario/fault_events.py):
 * the encoders' here (seeded noise, a one-tick glitch, a stuck encoder). A dead motor is the
 * drive's (drive.h). Read by cffi (ABI mode) for the state's type: plain declarations only. */
#ifndef CRSLAB_PLANT_FAULTS_H
#define CRSLAB_PLANT_FAULTS_H

#include <stdint.h>


/* Faults a scenario can inject; all off when zero. Noise is seeded (xorshift64*). */
typedef struct {
    uint64_t rng_state;          /* seed, never 0 */
    double noise_counts[3];      /* encoder noise, standard deviation in counts per joint */
    int64_t glitch_tick;         /* one tick where glitch_counts are added (-1: none) */
    int32_t glitch_counts[3];
    int32_t stuck_encoder[3];    /* 1: the encoder reading is frozen */
    int32_t dead_motor[3];       /* 1: the amplifier outputs nothing */
    int64_t stuck_counts[3];     /* frozen readings */
} crs_faults;

/* What joint `joint`'s encoder reports at `tick` (counts), from its true reading `counts`: plus
 * seeded noise (f->rng_state advances) and the glitch of its tick; a stuck encoder repeats the
 * last reading it reported (f->stuck_counts). */
int64_t crs_faulty_encoder_counts(crs_faults *f, int64_t tick, int joint, int64_t counts);

#endif
