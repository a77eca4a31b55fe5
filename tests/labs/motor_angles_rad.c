/* Test lab: leaves the arm to the scenario (zero torque) and prints the three motor angles lab()
 * receives, in rad with four decimals, every 10 ms: enough digits to see an offset, a resting
 * pose, encoder noise and glitches in the transcript. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
float printtheta1motor = 0, printtheta2motor = 0, printtheta3motor = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 10) == 0) {
        printtheta1motor = theta1motor;
        printtheta2motor = theta2motor;
        printtheta3motor = theta3motor;
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%ld %.4f %.4f %.4f\n\r", mycount - 1, printtheta1motor, printtheta2motor,
                  printtheta3motor);
}
