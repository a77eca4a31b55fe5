/* Test lab: watched variables of several types, as a student's lab declares them for the
 * course's MATLAB tools. Gen B (C2000Ware) style. The lab writes call_log[k] = 0.5 * k for its
 * first 8 calls; it prints `gain mode` every 100 calls, so writes to gain and mode show up in
 * the next print. */
#include "math.h"
#include "F28335Serial.h"

#define PI 3.1415926535897932384626433832795

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;
long mycount = 0;

#pragma DATA_SECTION(gain, ".my_vars")
float gain = 2.5;
#pragma DATA_SECTION(mode, ".my_vars")
int mode = 3;
#pragma DATA_SECTION(flags, ".my_vars")
Uint16 flags;
#pragma DATA_SECTION(call_log, ".my_arrs")
float call_log[8];
#pragma DATA_SECTION(limits, ".my_arrs")
long limits[3] = {10, 20, 30};

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount < 8) {
        call_log[mycount] = 0.5f * mycount;
    }
    if (mycount % 100 == 0) {
        UARTprint = 1;
    }
    Simulink_PlotVar1 = gain * sinf(2 * PI * mycount / 1000.0f);
    Simulink_PlotVar2 = mode;
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%.2f %d\n\r", gain, mode);
}
