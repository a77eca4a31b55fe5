/* Test lab: the course template's off-by-one. It saves a sample every 50 calls and resets the
 * index only after it has passed 99, so the 101st sample is written to theta1array[100]. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;

#pragma DATA_SECTION(theta1array, ".my_arrs")
float theta1array[100];
long arrayindex = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 50) == 0) {
        theta1array[arrayindex] = theta1motor;
        if (arrayindex >= 100) {
            arrayindex = 0;
        } else {
            arrayindex++;
        }
    }
    if ((mycount % 500) == 0) {
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld index %ld\n\r", mycount, arrayindex);
}
