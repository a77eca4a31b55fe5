/* Test lab (Gen B) with the printing function misspelled: it sets UARTprint every 500 calls,
 * but the framework finds no printing() to run, so nothing is printed, on the board as in crslab. */
#include "math.h"
#include "F28335Serial.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;
long mycount = 0;
float printtheta1motor = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0) {
        printtheta1motor = theta1motor;
        UARTprint = 1;
    }
    mycount++;
}

void printng(void)
{
    serial_printf(&SerialA, "%.2f\n\r", printtheta1motor);
}
