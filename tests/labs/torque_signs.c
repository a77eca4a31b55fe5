/* Test lab for Lab 1's torque-sign exercise, joint by joint: the watched variable torquejoint
 * (0: none, 1..3: that joint) selects which motor gets torqueunits (command units); the motor
 * angles are printed in degrees every 250 ms, so a positive torque must show a rising angle. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

#pragma DATA_SECTION(torquejoint, ".my_vars")
int torquejoint = 0;
#pragma DATA_SECTION(torqueunits, ".my_vars")
float torqueunits = 1.0;

long mycount = 0;
float printtheta1motor = 0, printtheta2motor = 0, printtheta3motor = 0;
int printjoint = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = (torquejoint == 1) ? torqueunits : 0;
    *tau2 = (torquejoint == 2) ? torqueunits : 0;
    *tau3 = (torquejoint == 3) ? torqueunits : 0;
    if ((mycount % 250) == 0) {
        printtheta1motor = theta1motor;
        printtheta2motor = theta2motor;
        printtheta3motor = theta3motor;
        printjoint = torquejoint;
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "joint %d: %.2f %.2f %.2f\n\r", printjoint, printtheta1motor * 180 / PI,
                  printtheta2motor * 180 / PI, printtheta3motor * 180 / PI);
}
