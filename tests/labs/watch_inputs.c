/* Test lab: shows what a scenario writes. Watched variables (a float, an int, a float array)
 * and the first three values Simulink sends down are printed every 100 ms; the torques stay 0. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

extern int SIMU_Var1_fromSIMU_16bit;
extern int SIMU_Var2_fromSIMU_16bit;
extern int SIMU_Var7_fromSIMU_16bit;

#pragma DATA_SECTION(gain, ".my_vars")
float gain = 1.5;
#pragma DATA_SECTION(mode, ".my_vars")
int mode = 0;
#pragma DATA_SECTION(table, ".my_arrs")
float table[4] = {0, 0, 0, 0};

long mycount = 0;
float printgain = 0;
int printmode = 0;
float printtable2 = 0;
int printsimu1 = 0, printsimu2 = 0, printsimu7 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 100) == 0) {
        printgain = gain;
        printmode = mode;
        printtable2 = table[2];
        printsimu1 = SIMU_Var1_fromSIMU_16bit;
        printsimu2 = SIMU_Var2_fromSIMU_16bit;
        printsimu7 = SIMU_Var7_fromSIMU_16bit;
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "gain %.2f mode %d table2 %.2f simu %d %d %d\n\r", printgain, printmode,
                  printtable2, printsimu1, printsimu2, printsimu7);
}
