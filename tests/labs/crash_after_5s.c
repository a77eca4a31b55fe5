/* Test lab: prints the motor angles every 500 ms like Lab 1, then at 5.1 s (call 1000) writes
 * through a null pointer, as a student's stray pointer would. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
float *gainptr = 0;
float printtheta1motor = 0, printtheta2motor = 0, printtheta3motor = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0) {
        printtheta1motor = theta1motor;
        printtheta2motor = theta2motor;
        printtheta3motor = theta3motor;
        SWI_post(&SWI_printf);
    }
    if (mycount == 1000) {
        *gainptr = 2.0f;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%.2f %.2f %.2f\n\r", printtheta1motor * 180 / PI,
                  printtheta2motor * 180 / PI, printtheta3motor * 180 / PI);
}
