/* Test lab: Lab 1's open-loop exercise at full torque. A constant *tau1 = 5 turns joint 1 until the
 * framework's safety envelope takes over; prints the `error` flag lab() receives. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
int last_error = 0;
float last_theta1 = 0;

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 5;
    *tau2 = 0;
    *tau3 = 0;
    if (error != last_error) {
        serial_printf(&SerialA, "error %d at %.3f rad\n\r", error, theta1motor);
    }
    last_error = error;
    last_theta1 = theta1motor;
    Simulink_PlotVar1 = theta1motor;
    Simulink_PlotVar2 = theta2motor;
    Simulink_PlotVar3 = theta3motor;
    Simulink_PlotVar4 = (float)error;
    mycount++;
}

void printing(void) {}
