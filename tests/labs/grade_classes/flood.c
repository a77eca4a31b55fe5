/* Grade-classes test lab (output limit): from call 1000 on prints a 60-character debug line
 * every millisecond, far more than the serial line carries. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

#pragma DATA_SECTION(gain, ".my_vars")
float gain = 1.5;

long mycount = 0;
long printcount = 0;
float printgain = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 250) == 0) {
        printcount = mycount;
        printgain = gain;
        SWI_post(&SWI_printf);
    }
    if (mycount >= 1000) {
        serial_printf(&SerialA, "debug %ld ..................................................\n\r", mycount);
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld gain %.2f\n\r", printcount, printgain);
}
