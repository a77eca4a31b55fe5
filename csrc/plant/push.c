/* The push at the end effector (see push.h). */
#include "push.h"

#include "crs_arm.h"

void crs_push_force(const crs_push *push, int64_t tick, double force_n[3])
{
    double sign = 1.0;
    if (!push->active || tick < push->start_tick) {
        sign = 0.0;
    } else if (push->half_period_ticks > 0 && ((tick - push->start_tick) / push->half_period_ticks) % 2 == 1) {
        sign = -1.0; /* the second half of each period of the square wave */
    }
    for (int k = 0; k < 3; ++k) force_n[k] = sign * push->force_n[k];
}

void crs_push_joint_torques(const double dh_rad[3], const double force_n[3], double tau_nm[3])
{
    double motor_rad[3], jac_in_per_rad[9];
    crs_dh_to_motor(dh_rad, motor_rad);
    crs_jacobian_motor(motor_rad, jac_in_per_rad);
    /* motor angles (j1, j2 + pi/2, j2 + j3): d/d j2 = d/d th2M + d/d th3M, d/d j3 = d/d th3M */
    for (int i = 0; i < 3; ++i) {
        double tau = 0.0;
        for (int k = 0; k < 3; ++k) {
            const double *row = &jac_in_per_rad[3 * k];
            const double d_dh = i == 0 ? row[0] : (i == 1 ? row[1] + row[2] : row[2]);
            tau += d_dh * force_n[k];
        }
        tau_nm[i] = CRS_M_PER_IN * tau;
    }
}

void crs_push_apply(crs_push *push, int64_t tick, const double dh_rad[3], double qfrc_nm[3])
{
    if (!push->active) {
        for (int k = 0; k < 3; ++k) push->now_n[k] = 0.0;
        return;
    }
    crs_push_force(push, tick, push->now_n);
    double tau_nm[3];
    crs_push_joint_torques(dh_rad, push->now_n, tau_nm);
    for (int j = 0; j < 3; ++j) qfrc_nm[j] += tau_nm[j];
}
