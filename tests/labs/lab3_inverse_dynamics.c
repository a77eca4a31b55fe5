/* A Lab 3-style test lab (Gen A): inverse-dynamics control of motors 2 and 3 with the course's
 * two-link model in motor angles, PD on motor 1, and the course's friction compensation.
 *
 * From where lab() first finds the arm, each joint follows a cubic to its target in move_s, then
 * holds it:
 *     a = thdd_des + Kp (th_des - th) + Kd (thd_des - thd)          (outer loop, rad/s^2)
 *     tau23 = D(th) a + C(th, thd) thd + G(th) + u_fric              (command units)
 * D = [[p1, -p3 sin(th3 - th2)], [-p3 sin(th3 - th2), p2]], C thd = [-p3 cos(th3 - th2) thd3^2,
 * p3 cos(th3 - th2) thd2^2], G = [-p4 g sin th2, -p5 g cos th3], with the course's p vector of
 * the bare arm, or, when use_mass_p is 1, its p vector with the added end mass. u_fric is the
 * course's friction table with its small band through zero below vmin.
 *
 * Every 100 ms it prints the three motor angles (rad) and the torques on motors 2 and 3. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

#pragma DATA_SECTION(use_mass_p, ".my_vars")
float use_mass_p = 1;
#pragma DATA_SECTION(target, ".my_arrs")
float target[3] = {0.3, 0.0, 0.2};
float move_s = 2.0;

float p_bare[5] = {0.0300, 0.0128, 0.0076, 0.0753, 0.0298};
float p_mass[5] = {0.0466, 0.0388, 0.0284, 0.1405, 0.1298};
float J1 = 0.0167;
float Kp = 2500.0, Kd = 100.0;

float Vpos[3] = {0.2513, 0.2500, 0.1922};
float Vneg[3] = {0.2477, 0.2870, 0.2132};
float Cpos[3] = {0.3637, 0.4759, 0.5339};
float Cneg[3] = {-0.2948, -0.5031, -0.5190};
float vmin[3] = {0.1, 0.05, 0.05};
float slope = 3.6;

float start[3];
float theta_old[3];
float omega_raw1[3], omega_raw2[3];
long mycount = 0;
float print_theta[3], print_tau[2];

static float friction(int j, float w)
{
    if (w > vmin[j]) return Vpos[j] * w + Cpos[j];
    if (w < -vmin[j]) return Vneg[j] * w + Cneg[j];
    return slope * w;
}

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    float th[3], w[3], qd[3], qdd[3], qdd_des[3], a[3];
    float *p = use_mass_p > 0.5 ? p_mass : p_bare;
    float t = mycount * 0.001;
    th[0] = theta1motor;
    th[1] = theta2motor;
    th[2] = theta3motor;
    if (mycount == 0) {
        for (int j = 0; j < 3; ++j) {
            start[j] = th[j];
            theta_old[j] = th[j];
        }
    }
    for (int j = 0; j < 3; ++j) {
        float raw = (th[j] - theta_old[j]) / 0.001;
        w[j] = (raw + omega_raw1[j] + omega_raw2[j]) / 3.0;
        omega_raw2[j] = omega_raw1[j];
        omega_raw1[j] = raw;
        theta_old[j] = th[j];
        /* cubic from start to target over move_s, then hold */
        float d = target[j] - start[j];
        if (t < move_s) {
            float s = t / move_s;
            qd[j] = start[j] + d * (3 * s * s - 2 * s * s * s);
            qdd[j] = d * (6 * s - 6 * s * s) / move_s;
            qdd_des[j] = d * (6 - 12 * s) / (move_s * move_s);
        } else {
            qd[j] = target[j];
            qdd[j] = 0;
            qdd_des[j] = 0;
        }
        a[j] = qdd_des[j] + Kp * (qd[j] - th[j]) + Kd * (qdd[j] - w[j]);
    }
    float s32 = sin(th[2] - th[1]), c32 = cos(th[2] - th[1]);
    *tau1 = J1 * a[0] + friction(0, w[0]);
    *tau2 = p[0] * a[1] - p[2] * s32 * a[2] - p[2] * c32 * w[2] * w[2] - p[3] * GRAV * sin(th[1])
            + friction(1, w[1]);
    *tau3 = -p[2] * s32 * a[1] + p[1] * a[2] + p[2] * c32 * w[1] * w[1] - p[4] * GRAV * cos(th[2])
            + friction(2, w[2]);

    if ((mycount % 100) == 0) {
        for (int j = 0; j < 3; ++j) print_theta[j] = th[j];
        print_tau[0] = *tau2;
        print_tau[1] = *tau3;
        SWI_post(&SWI_printf);
    }
    mycount++;
    (void)error;
}

void printing(void)
{
    serial_printf(&SerialA, "%.5f %.5f %.5f %.4f %.4f\n\r", print_theta[0], print_theta[1], print_theta[2],
                  print_tau[0], print_tau[1]);
}
