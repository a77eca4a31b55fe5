/* Test lab: every lab() call spins for about 3 ms of CPU, three times the DSP's 1 ms budget. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <time.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
volatile double sink = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    clock_t start = clock();
    while (clock() - start < CLOCKS_PER_SEC / 333) {
        sink += sin(theta1motor + sink);
    }
    mycount++;
}

void printing(void) {}
