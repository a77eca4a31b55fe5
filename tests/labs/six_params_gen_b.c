/* Test lab in the style of Lab 2, Gen B ("me446 starter"): lab() is defined with the six parameters
 * it uses, without the framework's trailing `int error`, as some teams' files do (the framework
 * declares lab() in its own file, so nothing checks the count). PD control holds joint 1 at 0.2 rad;
 * every 250 calls it prints the call count and joint 1's angle in degrees. */
#include "math.h"
#include "F28335Serial.h"

#define PI 3.1415926535897932384626433832795
#define TWOPI 6.283185307179586476925286766559
#define HALFPI 1.5707963267948966192313216916398
#define GRAV 9.81

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;

long mycount = 0;
float Kp1 = 40.0;
float Kd1 = 2.0;
float theta1_old = 0;
float printtheta1deg = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2, float *tau3)
{
    float omega1 = (theta1motor - theta1_old) / 0.001f;
    theta1_old = theta1motor;
    *tau1 = Kp1 * (0.2f - theta1motor) - Kd1 * omega1;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 250) == 0) {
        printtheta1deg = theta1motor * 180.0f / PI;
        UARTprint = 1;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "call %ld: theta1 %.2f deg\n\r", mycount, printtheta1deg);
}
