/* Test lab for crslab debug: counts its lab() calls, keeps the motor angle it was last handed,
 * and turns joint 1 with a small constant torque so that angle grows tick after tick. Prints the
 * count and the angle twice a second. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
float theta1_seen = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    theta1_seen = theta1motor;
    *tau1 = 0.5;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0) {
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.3f\n\r", mycount, theta1_seen);
}
