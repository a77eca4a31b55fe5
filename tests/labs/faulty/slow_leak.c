/* Test lab: every lab() call spins for 1 / SPIN_PER_S of a second of CPU and leaks LEAK_KB more of
 * memory, writing the first byte of each block (no NULL check, as a lab that copies one has none).
 * From call STUCK_FROM on (0: never) a call never returns: it spins and leaks on. Fast or slow, a
 * growing lab is ended by its memory limit; one that grows too little is stuck, whatever it grows. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <stdlib.h>
#include <time.h>

#define LEAK_KB 32768L
#define SPIN_PER_S 33
#define STUCK_FROM 0

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
long leaks = 0;
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
    do {
        clock_t start = clock();
        while (clock() - start < CLOCKS_PER_SEC / SPIN_PER_S) {
            sink += sin(theta1motor + sink);
        }
        char *block = malloc(LEAK_KB * 1024);
        block[0] = 1;
        blocks[leaks % 4096] = block;
        leaks++;
    } while (STUCK_FROM > 0 && mycount >= STUCK_FROM);
}

void printing(void) {}
