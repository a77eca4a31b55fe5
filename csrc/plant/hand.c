/* The test rig's hand: what moves the arm in Lab 1 (see hand.h). */
#include "hand.h"

#include "framework_facts.h"

void crs_hand_plan(const crs_hand *h, crs_hand_path *path)
{
    /* a minimum-jerk path (the quintic profile) from where the move started to the target */
    const double duration_s = (double)h->duration_ticks * CRS_TICK_S;
    path->planned = 0;
    if (h->duration_ticks > 0) {
        for (int j = 0; j < 3; ++j) {
            traj_profile move;
            traj_plan(&move, TRAJ_QUINTIC, h->start_dh_rad[j], h->target_dh_rad[j], duration_s, 0.0, 0.0);
            path->move[j] = move;
        }
        path->planned = 1;
    }
}

void crs_hand_step_along(const crs_hand_config *config, crs_hand *h, const crs_hand_path *hand_path, int64_t tick,
                         const double qpos_dh_rad[3], const double qvel_dh_rad_s[3])
{
    if (!h->active) {
        for (int j = 0; j < 3; ++j) h->force_nm[j] = 0.0;
        return;
    }
    const double t_s = (double)(tick - h->start_tick) * CRS_TICK_S;
    for (int j = 0; j < 3; ++j) {
        traj_sample path = {h->target_dh_rad[j], 0.0, 0.0, 0.0}; /* no duration: the target at once */
        if (hand_path->planned) path = traj_eval(&hand_path->move[j], t_s);
        const double err = path.q_rad - qpos_dh_rad[j];
        const double derr = path.qd_rad_s - qvel_dh_rad_s[j];
        double f = config->kp_nm_per_rad * err + config->ki_nm_per_rad_s * h->integral_rad_s[j]
                 + config->kd_nm_s_per_rad * derr;
        if (f > config->max_nm) {
            f = config->max_nm;
        } else if (f < -config->max_nm) {
            f = -config->max_nm;
        } else {
            h->integral_rad_s[j] += err * CRS_TICK_S; /* integrate only when not saturated */
        }
        h->force_nm[j] = f;
    }
}
