/* Test lab (a worker its runs share): prints its count every 100 calls; on its 301st call waits
 * for a flag nothing sets, and never returns. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
volatile int ready = 0;
volatile long spun = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount == 300) {
        while (!ready) spun++;
    }
    if ((mycount % 100) == 0) SWI_post(&SWI_printf);
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld\n\r", mycount);
}
