/* Hostile test lab: on its 1024th call writes through a pointer far outside its memory. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
float *far_away = (float *)0x7ffffff0;

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
    if (mycount == 1023) {
        *far_away = theta1motor;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);
}
