/* Test lab: leaves the arm alone (zero torque on every joint) and, every 100 s of lab() calls,
 * prints how far each motor angle has moved since the first call, in encoder counts (288 000 per
 * revolution). A Gen B ("me446 starter") file. */
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
float first[3];
float moved[3];

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    if (mycount == 0) {
        first[0] = theta1motor;
        first[1] = theta2motor;
        first[2] = theta3motor;
    }
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 100000) == 0) {
        moved[0] = (theta1motor - first[0]) / (PI / 144000.0);
        moved[1] = (theta2motor - first[1]) / (PI / 144000.0);
        moved[2] = (theta3motor - first[2]) / (PI / 144000.0);
        UARTprint = 1;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%ld %.2f %.2f %.2f\n\r", mycount / 1000, moved[0], moved[1], moved[2]);
}
