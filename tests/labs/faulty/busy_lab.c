/* Test lab: every lab() call runs the same long loop (100 000 rounds of a multiply and an add):
 * far more work than the DSP's tick leaves lab(), counted the same on every machine. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
volatile float sink = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    for (long i = 0; i < 100000; i++) {
        sink = sink * 0.5f + theta1motor;
    }
    mycount++;
}

void printing(void) {}
