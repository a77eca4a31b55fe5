/* Test lab for the course's host tools (MATLAB over SerialC, Simulink over SerialB), written the
 * way a Gen B "me446 starter" lab file is. As Lab 1's template does, it stores theta1motor in
 * theta1array every 50 ms, and beside it in timearray the time of each sample (ms), so a host
 * reading the 100 floats finds 100 consecutive multiples of 50 however late it reads. Kp1 is a
 * gain the host writes: its value is printed every 250 ms with the first two values Simulink
 * sent. */
#include <math.h>
#include "F28335Serial.h"

#define PI 3.1415926535897932384626433832795
#define TWOPI 6.283185307179586476925286766559
#define HALFPI 1.5707963267948966192313216916398
#define GRAV 9.81

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;

long mycount = 0;

#pragma DATA_SECTION(whattoprint, ".my_vars")
float whattoprint = 1.25;
#pragma DATA_SECTION(Kp1, ".my_vars")
float Kp1 = 12.5;
#pragma DATA_SECTION(samples, ".my_vars")
float samples = 0;
#pragma DATA_SECTION(mode, ".my_vars")
int mode = -2;

#pragma DATA_SECTION(theta1array, ".my_arrs")
float theta1array[100];
#pragma DATA_SECTION(timearray, ".my_arrs")
float timearray[100];
long arrayindex = 0;

extern int SIMU_Var1_fromSIMU_16bit;
extern int SIMU_Var2_fromSIMU_16bit;

float printKp1 = 0;
int printsimu1 = 0, printsimu2 = 0, printmode = 0;

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
        printmode = mode;
        UARTprint = 1;
    }

    Simulink_PlotVar1 = mycount * 0.001;
    Simulink_PlotVar2 = Kp1;
    Simulink_PlotVar3 = SIMU_Var1_fromSIMU_16bit;
    Simulink_PlotVar4 = -2.0 / 3.0;

    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "Kp1 %.2f simu %d %d mode %d\n\r", printKp1, printsimu1, printsimu2, printmode);
}
