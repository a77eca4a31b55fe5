/* Test lab in the style of Lab 2, Gen B, with C89 habits: it calls malloc() and free() without
 * including <stdlib.h>, calls its own average() before defining it without a prototype, and declares
 * a counter without a type (implicit int). TI's compiler warns and builds each. It keeps the last 8
 * values of joint 2's angle (in hundredths of a degree) in a malloc'd ring and prints their average
 * every 500 calls. */
#include "math.h"
#include "F28335Serial.h"

#define PI 3.1415926535897932384626433832795

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;

long mycount = 0;
int *ring = 0;
static filled = 0;
int printavg = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    if (ring == 0) {
        ring = malloc(8 * sizeof(int));
    }
    ring[mycount % 8] = (int)(theta2motor * 18000 / PI);
    if (filled < 8) filled++;
    if ((mycount % 500) == 0) {
        printavg = average(ring, filled);
        UARTprint = 1;
    }
    mycount++;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
}

int average(int *values, int n)
{
    long sum = 0;
    int i;
    for (i = 0; i < n; i++) sum += values[i];
    return (int)(sum / n);
}

void printing(void)
{
    serial_printf(&SerialA, "joint 2 average %d (0.01 deg) after %ld calls\n\r", printavg, mycount);
    if (mycount >= 1000) {
        free(ring);
        ring = 0;
        filled = 0;
    }
}
