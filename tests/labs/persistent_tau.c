/* Test lab: the framework's tau variables persist between calls. Only the first call writes
 * tau2 (0.5) and tau1 (40, beyond the +-5 clamp); later calls write nothing. Prints the tick
 * count of its first call. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error; (void)tau3;
    if (mycount == 0) {
        *tau1 = 40.0;
        *tau2 = 0.5;
        serial_printf(&SerialA, "first call\n\r");
    }
    mycount++;
}

void printing(void) {}
