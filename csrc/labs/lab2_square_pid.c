/* crslab's calibration lab: Lab 2's PID square wave on all three joints, written the way a
 * Gen A lab file is. It is the controller of the real-arm recording the arm model was fitted
 * to (models/crs_arm/README.md), quirks included, so `crslab identify` can rerun it:
 *
 * - Every 1000 calls (1 s, the first at the first call) each joint's reference toggles between
 *   0 and pi/6 (motor angles, rad).
 * - Velocity: the mean of the last three raw backward differences.
 * - PID in command units, u = Kp e - Kd Omega + Ki I, the integral by the trapezoid rule and
 *   zeroed whenever |e| leaves the joint's window.
 * - Anti-windup as the recorded file had it: when joint 1's command is beyond +-5, EVERY
 *   joint's integral is put back to its previous value (joint 1 decides for all three).
 * - The framework clamps the commands to +-5.
 *
 * Simulink_PlotVar1..3 are the three motor angles (rad) as lab() receives them; PlotVar4 is
 * joint 1's reference (rad). Run it on your own arm with the course's Simulink model, save the
 * scope, and `crslab identify` calibrates crslab's arm to yours. Every 500 ms it prints the
 * three references and the three angles (rad); the control card's LED blinks once a second. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.424;
float offset_Enc3_rad = 0.209;

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

long mycount = 0;

/* gains, command units per rad, per rad/s and per rad.s */
#pragma DATA_SECTION(Kp1, ".my_vars")
float Kp1 = 30.0;
#pragma DATA_SECTION(Kp2, ".my_vars")
float Kp2 = 30.0;
#pragma DATA_SECTION(Kp3, ".my_vars")
float Kp3 = 30.0;
#pragma DATA_SECTION(Kd1, ".my_vars")
float Kd1 = 1.75;
#pragma DATA_SECTION(Kd2, ".my_vars")
float Kd2 = 1.75;
#pragma DATA_SECTION(Kd3, ".my_vars")
float Kd3 = 1.75;
#pragma DATA_SECTION(Ki1, ".my_vars")
float Ki1 = 200.0;
#pragma DATA_SECTION(Ki2, ".my_vars")
float Ki2 = 300.0;
#pragma DATA_SECTION(Ki3, ".my_vars")
float Ki3 = 300.0;

/* the integral is only kept while the error is inside this window (rad) */
float window1 = 0.017;
float window2 = 0.013;
float window3 = 0.013;

float theta1d = 0, theta2d = 0, theta3d = 0;
float theta1_old = 0, theta2_old = 0, theta3_old = 0;
float Omega1_raw1 = 0, Omega1_raw2 = 0;
float Omega2_raw1 = 0, Omega2_raw2 = 0;
float Omega3_raw1 = 0, Omega3_raw2 = 0;
float e1_old = 0, e2_old = 0, e3_old = 0;
float I1 = 0, I2 = 0, I3 = 0;
float I1_old = 0, I2_old = 0, I3_old = 0;

float print_d[3], print_theta[3];

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    float Omega1_raw, Omega2_raw, Omega3_raw;
    float Omega1, Omega2, Omega3;
    float e1, e2, e3;
    float u1, u2, u3;

    /* square wave: toggle every second */
    if ((mycount % 1000) == 0) {
        if (theta1d > 0.25) {
            theta1d = 0;
        } else {
            theta1d = PI / 6;
        }
        if (theta2d > 0.25) {
            theta2d = 0;
        } else {
            theta2d = PI / 6;
        }
        if (theta3d > 0.25) {
            theta3d = 0;
        } else {
            theta3d = PI / 6;
        }
    }

    /* velocity: mean of the last three raw differences */
    Omega1_raw = (theta1motor - theta1_old) / 0.001;
    Omega2_raw = (theta2motor - theta2_old) / 0.001;
    Omega3_raw = (theta3motor - theta3_old) / 0.001;
    Omega1 = (Omega1_raw + Omega1_raw1 + Omega1_raw2) / 3.0;
    Omega2 = (Omega2_raw + Omega2_raw1 + Omega2_raw2) / 3.0;
    Omega3 = (Omega3_raw + Omega3_raw1 + Omega3_raw2) / 3.0;

    e1 = theta1d - theta1motor;
    e2 = theta2d - theta2motor;
    e3 = theta3d - theta3motor;

    /* integral, trapezoid rule; zero outside the window */
    I1 = I1_old + (e1_old + e1) / 2 * 0.001;
    I2 = I2_old + (e2_old + e2) / 2 * 0.001;
    I3 = I3_old + (e3_old + e3) / 2 * 0.001;
    if (fabs(e1) > window1) {
        I1 = 0;
        I1_old = 0;
    }
    if (fabs(e2) > window2) {
        I2 = 0;
        I2_old = 0;
    }
    if (fabs(e3) > window3) {
        I3 = 0;
        I3_old = 0;
    }

    u1 = Kp1 * e1 - Kd1 * Omega1 + Ki1 * I1;
    u2 = Kp2 * e2 - Kd2 * Omega2 + Ki2 * I2;
    u3 = Kp3 * e3 - Kd3 * Omega3 + Ki3 * I3;

    /* anti-windup: joint 1's command decides for all three */
    if (fabs(u1) > 5) {
        I1 = I1_old;
        I2 = I2_old;
        I3 = I3_old;
    }

    I1_old = I1;
    I2_old = I2;
    I3_old = I3;
    e1_old = e1;
    e2_old = e2;
    e3_old = e3;
    theta1_old = theta1motor;
    theta2_old = theta2motor;
    theta3_old = theta3motor;
    Omega1_raw2 = Omega1_raw1;
    Omega1_raw1 = Omega1_raw;
    Omega2_raw2 = Omega2_raw1;
    Omega2_raw1 = Omega2_raw;
    Omega3_raw2 = Omega3_raw1;
    Omega3_raw1 = Omega3_raw;

    *tau1 = u1;
    *tau2 = u2;
    *tau3 = u3;

    Simulink_PlotVar1 = theta1motor;
    Simulink_PlotVar2 = theta2motor;
    Simulink_PlotVar3 = theta3motor;
    Simulink_PlotVar4 = theta1d;

    if ((mycount % 500) == 0) {
        print_d[0] = theta1d;
        print_d[1] = theta2d;
        print_d[2] = theta3d;
        print_theta[0] = theta1motor;
        print_theta[1] = theta2motor;
        print_theta[2] = theta3motor;
        SWI_post(&SWI_printf);
    }
    if ((mycount % 500) == 0) {
        GpioDataRegs.GPBTOGGLE.bit.GPIO34 = 1;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "des %.3f %.3f %.3f  theta %.3f %.3f %.3f\n\r", print_d[0], print_d[1],
                  print_d[2], print_theta[0], print_theta[1], print_theta[2]);
}
