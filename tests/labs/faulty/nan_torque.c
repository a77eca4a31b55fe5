/* Test lab: returns NaN in tau2 from its 1000th call on (0/0 from a bad velocity estimate). */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <stdlib.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
volatile float dtheta = 0.0f;
volatile float dt = 0.0f;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0) {
        SWI_post(&SWI_printf);
    }
    if (mycount >= 999) {
        *tau2 = dtheta / dt;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);

}
