/* Test lab, Gen B ("me446 starter") style: prints its call count every 500 ms, and at call 1000
 * (t = 5.1 s) a 152-character line, which overflows the board's 136-byte serial_printf buffer. */
#include "math.h"
#include "F28335Serial.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;
long mycount = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount % 500 == 0) {
        UARTprint = 1;
    }
    mycount++;
}

void printing(void)
{
    if (mycount - 1 == 1000) {
        serial_printf(&SerialA, "%0150ld\n\r", mycount - 1); /* 150 digits and the line end */
    } else {
        serial_printf(&SerialA, "call %ld\n\r", mycount - 1);
    }
}
