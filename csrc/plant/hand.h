/* The test rig's hand (crs_hand): a bounded PID that pulls the DH joints along a
 * minimum-jerk path, set by a scenario's hand moves (crslab/scenario). Internal to the board; read
 * by cffi only in tests. */
#ifndef CRSLAB_HAND_H
#define CRSLAB_HAND_H

#include <stdint.h>

#include "traj_profiles.h"

/* The hand that moves the arm in Lab 1: a bounded PID pulling the DH joints along a
 * minimum-jerk path from where the move started to the target, then holding there. Split as
 * MuJoCo splits mjModel and mjData: its gains are what a run is configured with; its move (set by
 * a scenario's events between chunks, as a user sets mjData's inputs) and what it pulls with are
 * what the run changes. */
typedef struct {
    double kp_nm_per_rad, ki_nm_per_rad_s, kd_nm_s_per_rad, max_nm; /* gains and force bound */
} crs_hand_config;

typedef struct {
    int32_t active;              /* 0: not touching the arm */
    int32_t pad;
    int64_t start_tick, duration_ticks;
    double start_dh_rad[3], target_dh_rad[3];
    double integral_rad_s[3];
    double force_nm[3];          /* last applied generalized force on j1..j3, N.m */
} crs_hand;

/* The hand's path: per joint a minimum-jerk move from where it started to the target (planned: 1),
 * or none (0: the target at once). A move starts between chunks of ticks (a scenario event), so
 * the path is planned once per chunk and only evaluated every tick. */
typedef struct {
    int32_t planned;
    traj_profile move[3];
} crs_hand_path;
void crs_hand_plan(const crs_hand *h, crs_hand_path *path);
/* Pull the arm with the hand `h` (gains `config`) along `path` (crs_hand_plan of h) at `tick`, the
 * arm's DH joints at qpos_dh_rad (rad) moving at qvel_dh_rad_s (rad/s): writes h->force_nm (and
 * its integral). */
void crs_hand_step_along(const crs_hand_config *config, crs_hand *h, const crs_hand_path *path, int64_t tick,
                         const double qpos_dh_rad[3], const double qvel_dh_rad_s[3]);

#endif
