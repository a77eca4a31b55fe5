/* Test lab in the style of Lab 1, Gen A ("CRSRobot"), written the old way: lab() and printing() are
 * K&R-style definitions (the parameters' types after the list), which C89 and TI's compiler take;
 * on the C28x the promoted `double` of a K&R float parameter is a float too. Every 500 calls it
 * prints the call count and the three motor angles in degrees. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
float printtheta[3];

void lab(theta1motor, theta2motor, theta3motor, tau1, tau2, tau3, error)
float theta1motor, theta2motor, theta3motor;
float *tau1, *tau2, *tau3;
int error;
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0) {
        printtheta[0] = theta1motor * 180 / PI;
        printtheta[1] = theta2motor * 180 / PI;
        printtheta[2] = theta3motor * 180 / PI;
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void printing()
{
    serial_printf(&SerialA, "%ld %.2f %.2f %.2f\n\r", mycount, printtheta[0], printtheta[1], printtheta[2]);
}
