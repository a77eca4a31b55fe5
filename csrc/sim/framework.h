/* Internal: the pieces of the real framework's 1 ms tick (crs-facts section 2). */
#ifndef CRSLAB_FRAMEWORK_H
#define CRSLAB_FRAMEWORK_H

#include "sim.h"

/* Encoder angles (rad) the framework hands to lab(), from the plant's true motor angles. */
void crs_read_encoders(crs_sim *sim, const double motor_rad[3], double enc_rad[3]);
/* The framework's PD hold controller toward the last in-envelope pose, command units. */
void crs_hold_controller(const crs_sim *sim, double out[3]);
/* Pull the arm with the hand: writes sim->hand.force_nm. */
void crs_hand_step(crs_sim *sim);

#endif
