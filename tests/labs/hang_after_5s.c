/* Test lab: prints the motor angles every 500 ms, then at 5.1 s (call 1000) waits in lab() for
 * a flag nothing ever sets, as a student's busy-wait would: the real board hangs. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
volatile int ready = 0;
float printtheta1motor = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0) {
        printtheta1motor = theta1motor;
        SWI_post(&SWI_printf);
    }
    if (mycount == 1000) {
        while (!ready) {
        }
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%.2f\n\r", printtheta1motor * 180 / PI);
}
