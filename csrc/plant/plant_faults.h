/* Faults a scenario injects on the plant's hardware (crs_faults, sim.h; crslab/scenario/fault_events.py):
 * the encoders' here (seeded noise, a one-tick glitch, a stuck encoder). A dead motor is the
 * drive's (drive.h). Internal to the board; not read by cffi. */
#ifndef CRSLAB_PLANT_FAULTS_H
#define CRSLAB_PLANT_FAULTS_H

#include <stdint.h>

#include "sim.h"

/* What joint `joint`'s encoder reports at `tick` (counts), from its true reading `counts`: plus
 * seeded noise (f->rng_state advances) and the glitch of its tick; a stuck encoder repeats the
 * last reading it reported (f->stuck_counts). */
int64_t crs_faulty_encoder_counts(crs_faults *f, int64_t tick, int joint, int64_t counts);

#endif
