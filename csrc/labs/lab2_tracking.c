/* crslab's Lab 2-style tracking lab, written the way a Gen A lab file is.
 *
 * It follows joint-space waypoints with PD control plus inertia feedforward, as Lab 2 asks:
 *   tau = J qdd_des + Kp (q_des - q) + Kd (qd_des - qd)       (command units, motor angles)
 * with the course's inertias (J1 = 0.0167, J2 = p1 = 0.0300, J3 = p2 = 0.0128) and the velocity
 * from a backward difference averaged over the last three ticks. The trajectory is planned here,
 * in lab(), with crslab's trajectory profiles (traj_profiles.h): first a quintic move from where
 * the arm rests to the first waypoint (approach_s), a pause (hold_s), then one synchronized
 * rest-to-rest move per waypoint pair, each taking wp_duration_s[i].
 *
 * The waypoints are watched variables (written by `crslab board --waypoints pts.csv` before the
 * first tick, or from MATLAB on the real board): wp_motor_rad holds n_waypoints rows of three
 * motor angles (rad). Every 500 ms it prints the desired angles, the measured angles and their
 * difference, in degrees. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include "traj_profiles.h"

#define MAX_WAYPOINTS 20

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

#pragma DATA_SECTION(n_waypoints, ".my_vars")
float n_waypoints = 0;
#pragma DATA_SECTION(wp_profile, ".my_vars")
float wp_profile = 0; /* 0 Li sinusoidal jerk, 1 quintic, 2 cubic, 3 trapezoid */
#pragma DATA_SECTION(wp_vmax_rad_s, ".my_vars")
float wp_vmax_rad_s = 0; /* joint speed limit the waypoints were planned with; 0: none */
#pragma DATA_SECTION(approach_s, ".my_vars")
float approach_s = 2.0;
#pragma DATA_SECTION(hold_s, ".my_vars")
float hold_s = 0.5;
#pragma DATA_SECTION(wp_motor_rad, ".my_arrs")
float wp_motor_rad[3 * MAX_WAYPOINTS];
#pragma DATA_SECTION(wp_duration_s, ".my_arrs")
float wp_duration_s[MAX_WAYPOINTS];

/* gains, command units per rad and per rad/s */
#pragma DATA_SECTION(Kp, ".my_arrs")
float Kp[3] = {60.0, 60.0, 60.0};
#pragma DATA_SECTION(Kd, ".my_arrs")
float Kd[3] = {2.2, 2.2, 2.2};
float J[3] = {0.0167, 0.0300, 0.0128}; /* the course's inertias, command units s^2/rad */

long mycount = 0;
int planned = 0;
int n_segments = 0;
traj_profile approach[3];
traj_profile segments[3 * (MAX_WAYPOINTS - 1)];
double segment_start_s[MAX_WAYPOINTS - 1];

float theta_old[3] = {0, 0, 0};
float omega_old1[3] = {0, 0, 0};
float omega_old2[3] = {0, 0, 0};

float print_desired[3], print_actual[3];

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

static void plan(const float theta[3])
{
    const traj_kind kind = (traj_kind)(int)wp_profile;
    int n = (int)n_waypoints;
    if (n > MAX_WAYPOINTS) n = MAX_WAYPOINTS;
    for (int j = 0; j < 3; ++j) {
        const double goal = n > 0 ? wp_motor_rad[j] : theta[j];
        traj_plan(&approach[j], TRAJ_QUINTIC, theta[j], goal, approach_s, 0.0, 0.0);
    }
    double start = approach_s + hold_s;
    n_segments = n > 1 ? n - 1 : 0;
    for (int i = 0; i < n_segments; ++i) {
        double q0[3], qf[3];
        for (int j = 0; j < 3; ++j) {
            q0[j] = wp_motor_rad[3 * i + j];
            qf[j] = wp_motor_rad[3 * (i + 1) + j];
        }
        const double vmax[3] = {wp_vmax_rad_s, wp_vmax_rad_s, wp_vmax_rad_s};
        traj_plan_synchronized(&segments[3 * i], 3, kind, q0, qf, wp_duration_s[i], vmax, NULL, NULL);
        segment_start_s[i] = start;
        start += wp_duration_s[i];
    }
    planned = 1;
}

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)error;
    const float theta[3] = {theta1motor, theta2motor, theta3motor};
    float *tau[3] = {tau1, tau2, tau3};
    if (!planned) {
        plan(theta);
        for (int j = 0; j < 3; ++j) theta_old[j] = theta[j];
    }
    const double t = mycount * 0.001; /* seconds since the first call */
    traj_sample desired[3];
    if (n_segments == 0 || t < segment_start_s[0]) {
        for (int j = 0; j < 3; ++j) desired[j] = traj_eval(&approach[j], t);
    } else {
        traj_path_eval(segments, segment_start_s, (size_t)n_segments, 3, t, desired);
    }
    for (int j = 0; j < 3; ++j) {
        /* velocity: backward difference averaged over three ticks */
        float omega = (theta[j] - theta_old[j]) / 0.001;
        omega = (omega + omega_old1[j] + omega_old2[j]) / 3.0;
        theta_old[j] = theta[j];
        omega_old2[j] = omega_old1[j];
        omega_old1[j] = omega;

        *tau[j] = J[j] * desired[j].qdd_rad_s2 + Kp[j] * (desired[j].q_rad - theta[j])
                + Kd[j] * (desired[j].qd_rad_s - omega);
    }
    if ((mycount % 500) == 0) {
        for (int j = 0; j < 3; ++j) {
            print_desired[j] = desired[j].q_rad;
            print_actual[j] = theta[j];
        }
        SWI_post(&SWI_printf);
    }
    Simulink_PlotVar1 = desired[1].q_rad;
    Simulink_PlotVar2 = theta2motor;
    Simulink_PlotVar3 = desired[2].q_rad;
    Simulink_PlotVar4 = theta3motor;
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "desired %.2f %.2f %.2f  actual %.2f %.2f %.2f  error %.3f %.3f %.3f\n\r",
                  print_desired[0] * 180 / PI, print_desired[1] * 180 / PI, print_desired[2] * 180 / PI,
                  print_actual[0] * 180 / PI, print_actual[1] * 180 / PI, print_actual[2] * 180 / PI,
                  (print_desired[0] - print_actual[0]) * 180 / PI,
                  (print_desired[1] - print_actual[1]) * 180 / PI,
                  (print_desired[2] - print_actual[2]) * 180 / PI);
}
