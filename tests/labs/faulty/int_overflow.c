/* Test lab: a 32-bit tick counter scaled by 1000 overflows (on the C28x int is 16 bits and it
 * would overflow far sooner); signed overflow is undefined behaviour. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
Int32 elapsed_us = 2147000000;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    elapsed_us = elapsed_us + 1000;
    mycount++;
}

void printing(void) {}
