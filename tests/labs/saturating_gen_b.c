/* Test lab, Gen B ("me446 starter") style: a saturated controller. For its first 2 s it commands
 * +4.5 and -4.5 units on joint 1 on alternate calls (beyond the motor board's 4-unit limit, so
 * the arm barely moves); then 0 for 0.5 s; then a steady 1 unit. Prints the call count whenever
 * its command changes phase. */
#include "math.h"
#include "F28335Serial.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;
long mycount = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    if (mycount < 2000) {
        *tau1 = (mycount % 2 == 0) ? 4.5 : -4.5;
    } else if (mycount < 2500) {
        *tau1 = 0;
    } else {
        *tau1 = 1.0;
    }
    *tau2 = 0;
    *tau3 = 0;
    if (mycount == 0 || mycount == 2000 || mycount == 2500) {
        UARTprint = 1;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "call %ld\n\r", mycount - 1);
}
