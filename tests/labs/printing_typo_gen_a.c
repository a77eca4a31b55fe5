/* Test lab (Gen A) with the printing function misspelled: it posts SWI_printf every 500 calls,
 * but the framework finds no printing() to run, so nothing is printed, on the board as in crslab. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
float printtheta1motor = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0) {
        printtheta1motor = theta1motor;
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void Printing(void)
{
    serial_printf(&SerialA, "%.2f\n\r", printtheta1motor);
}
