/* Test lab, Gen B ("me446 starter") style: an int counter incremented on every call, as the course's
 * mycount is, but declared int. On the C28x an int is 16 bits: the 32,767th call leaves it at 32767
 * and the 32,768th wraps it to -32768. The lab prints it on those two calls and on the first. */
#include "math.h"
#include "F28335Serial.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;
int mycount = 0;
long calls = 0;     /* a 32-bit count of the same calls */

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    mycount++;
    calls++;
    if (calls == 1 || calls == 32767 || calls == 32768) {
        UARTprint = 1;
    }
}

void printing(void)
{
    serial_printf(&SerialA, "call %ld mycount %d\n\r", calls, mycount);
}
