/* Test lab (Gen B, in the course's style) whose arithmetic gives other results on the C28x, where
 * int is 16 bits, long 32 and double 32: a product of ints past 32767, an int counter compared
 * with a bound it can never reach, a constant too big for an int, and a whole number a 32-bit
 * double cannot hold exactly. On the host all of them behave. It prints the first two. */
#include "math.h"
#include "F28335Serial.h"

#define PI 3.1415926535897932384626433832795

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;

int mycount = 0;
int area_in2 = 300 * 300;            /* C28X: int product */
long area_ok = 300L * 300;           /* long: the same on both */
int ticks_per_minute = 60000;        /* C28X: too big for an int */
double counts_per_rev = 16777217;    /* C28X: a 32-bit double rounds it */
float half = 0.5;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount > 40000) {           /* C28X: always false for a 16-bit int */
        mycount = 0;
    }
    if ((mycount % 500) == 0) {
        UARTprint = 1;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%d %ld\n\r", area_in2, area_ok);
}
