/* The test rig's hand (crs_hand, sim.h): a bounded PID that pulls the DH joints along a
 * minimum-jerk path, set by a scenario's hand moves (crslab/scenario). Internal to the board; read
 * by cffi only in tests. */
#ifndef CRSLAB_HAND_H
#define CRSLAB_HAND_H

#include "sim.h"
#include "traj_profiles.h"

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
