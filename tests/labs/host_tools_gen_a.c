/* Test lab for the course's host tools (MATLAB over SerialC, Simulink over SerialB), written the
 * way a Gen A "CRSRobot" lab file is. As Lab 1's template does, it stores theta1motor in
 * theta1array every 50 ms, and beside it in timearray the time of each sample (ms), so a host
 * reading the 100 floats finds 100 consecutive multiples of 50 however late it reads. Kp1 is a
 * gain the host writes: its value is printed every 250 ms with the first two values Simulink
 * sent. whattoprint = 1.25 sits first in .my_vars, at the address of docs/host-tools.md's
 * worked vectors. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

long mycount = 0;

#pragma DATA_SECTION(whattoprint, ".my_vars")
float whattoprint = 1.25;
#pragma DATA_SECTION(Kp1, ".my_vars")
float Kp1 = 12.5;
#pragma DATA_SECTION(samples, ".my_vars")
float samples = 0;

#pragma DATA_SECTION(theta1array, ".my_arrs")
float theta1array[100];
#pragma DATA_SECTION(timearray, ".my_arrs")
float timearray[100];
long arrayindex = 0;

extern int SIMU_Var1_fromSIMU_16bit;
extern int SIMU_Var2_fromSIMU_16bit;

float printKp1 = 0;
int printsimu1 = 0, printsimu2 = 0;

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;

    /* save past states every 50 ms */
    if ((mycount % 50) == 0) {
        theta1array[arrayindex] = theta1motor;
        timearray[arrayindex] = mycount;
        if (samples < 100) {
            samples = samples + 1;
        }
        if (arrayindex >= 99) {
            arrayindex = 0;
        } else {
            arrayindex++;
        }
    }

    if ((mycount % 250) == 0) {
        printKp1 = Kp1;
        printsimu1 = SIMU_Var1_fromSIMU_16bit;
        printsimu2 = SIMU_Var2_fromSIMU_16bit;
        SWI_post(&SWI_printf);
    }

    Simulink_PlotVar1 = mycount * 0.001;
    Simulink_PlotVar2 = Kp1;
    Simulink_PlotVar3 = SIMU_Var1_fromSIMU_16bit;
    Simulink_PlotVar4 = -2.0 / 3.0;

    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "Kp1 %.2f simu %d %d\n\r", printKp1, printsimu1, printsimu2);
}
