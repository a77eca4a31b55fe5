/* Test lab: the 10th lab() call never returns. It spins, and every 100 ms of its CPU it leaks
 * LEAK_KB more, writing the first byte of each block (no NULL check, as a lab that copies one has
 * none). Leaking fast, it is filling its memory, which its memory limit ends; leaking slowly, it
 * is stuck. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <stdlib.h>
#include <time.h>

#define LEAK_KB 65536L

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
volatile double sink = 0;
char *blocks[4096]; /* kept, so nothing is freed */

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    mycount++;
    for (long n = 0; mycount >= 10; n++) {
        clock_t start = clock();
        while (clock() - start < CLOCKS_PER_SEC / 10) {
            sink += sin(theta1motor + sink);
        }
        char *block = malloc(LEAK_KB * 1024);
        block[0] = 1;
        blocks[n % 4096] = block;
    }
}

void printing(void) {}
