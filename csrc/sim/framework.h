/* Internal: the pieces of the real framework's 1 ms tick (docs/framework.md sections 3 and 4). */
#ifndef CRSLAB_FRAMEWORK_H
#define CRSLAB_FRAMEWORK_H

#include "sim.h"
#include "traj_profiles.h"

/* Encoder angles (rad) the framework hands to lab(), from the plant's true motor angles. */
void crs_read_encoders(crs_sim *sim, const double motor_rad[3], double enc_rad[3]);
/* The hold controller's every-tick update (from tick 0 on): velocity filter and output
 * h->out for this tick's angles, toward the references as they stand. */
void crs_hold_update(crs_hold *h, const double enc_rad[3]);
/* Inside the envelope (from the startup gate on, after lab()): the references follow the arm. */
void crs_hold_follow(crs_hold *h, const double enc_rad[3]);
/* Outside: a reference more than CRS_HOLD_REANCHOR_RAD from its angle moves to the angle
 * (effective next tick), so an arm pushed far out is held about where it is. */
void crs_hold_reanchor(crs_hold *h, const double enc_rad[3]);
/* The hand's path: per joint a minimum-jerk move from where it started to the target (planned: 1),
 * or none (0: the target at once). A move starts between chunks of ticks (a scenario event), so
 * the path is planned once per chunk and only evaluated every tick. */
typedef struct {
    int32_t planned;
    traj_profile move[3];
} crs_hand_path;
void crs_hand_plan(const crs_hand *h, crs_hand_path *path);
/* Pull the arm with the hand along `path` (crs_hand_plan of sim->hand): writes sim->hand.force_nm. */
void crs_hand_step_along(crs_sim *sim, const crs_hand_path *path);

#endif
