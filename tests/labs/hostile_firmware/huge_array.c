/* Hostile test lab: a static array of 10 million floats (40 MB, 20 M words on the C28x), far more
 * than the F28335's data memory. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
float history[10000000];

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    history[mycount % 10000000] = theta1motor;
    mycount++;
}

void printing(void) {}
