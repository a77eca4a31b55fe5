/* Test lab: allocates 64 MB more on every call from its 1024th call on and fills it (a leak in
 * a loop): a memory limit must stop it, not the machine. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <stdlib.h>
#include <string.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
long leaked_mb = 0;
char *blocks[4096]; /* kept, so nothing is freed */

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount >= 1023) {
        char *block = malloc(64L * 1024 * 1024);
        memset(block, 1, 64L * 1024 * 1024); /* no NULL check, as in the lab it copies */
        blocks[mycount % 4096] = block;
        leaked_mb += 64;
    }
    mycount++;
}

void printing(void) {}
