/* Test lab for crslab sweep: PD control of motor 2 to a watched target, with a constant torque
 * on motor 1 and motor 3 held at its starting angle. Gains and torques are watched variables,
 * so a sweep can vary them (var:Kp2, var:tau1_open). Simulink_PlotVar1..3 are the motor angles,
 * PlotVar4 the target of motor 2; prints the three angles every 250 ms. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

#pragma DATA_SECTION(Kp2, ".my_vars")
float Kp2 = 20.0;
#pragma DATA_SECTION(Kd2, ".my_vars")
float Kd2 = 1.0;
#pragma DATA_SECTION(target2, ".my_vars")
float target2 = 0.1;
#pragma DATA_SECTION(tau1_open, ".my_vars")
float tau1_open = 0.0;
#pragma DATA_SECTION(steps, ".my_vars")
int steps = 3;
#pragma DATA_SECTION(gains, ".my_arrs")
float gains[2] = {1.0, 1.0};

long mycount = 0;
float theta2_old = 0;
float theta3_start = 0;
float print1 = 0, print2 = 0, print3 = 0;

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    float omega2;
    if (mycount == 0) {
        theta2_old = theta2motor;
        theta3_start = theta3motor;
    }
    omega2 = (theta2motor - theta2_old) / 0.001f;
    theta2_old = theta2motor;
    *tau1 = tau1_open;
    *tau2 = gains[0] * (Kp2 * (target2 - theta2motor) - Kd2 * omega2);
    *tau3 = gains[1] * 20.0f * (theta3_start - theta3motor);
    Simulink_PlotVar1 = theta1motor;
    Simulink_PlotVar2 = theta2motor;
    Simulink_PlotVar3 = theta3motor;
    Simulink_PlotVar4 = target2;
    if ((mycount % 250) == 0) {
        print1 = theta1motor;
        print2 = theta2motor;
        print3 = theta3motor;
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%.3f %.3f %.3f\n\r", print1, print2, print3);
}
