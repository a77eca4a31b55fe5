/* Test lab, Gen B ("me446 starter") style: prints the motor angle every 500 ms, then at 5.1 s
 * (call 1000) waits inside lab() for a flag that nothing sets while lab() runs: an ordinary global,
 * not volatile. Built with the optimisation off, as the course's projects are, the board reads the
 * flag from memory on every pass and spins until the motor board cuts out; a compiler allowed to
 * assume that a loop without side effects ends would drop the loop. */
#include "math.h"
#include "F28335Serial.h"

#define PI 3.1415926535897932384626433832795

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;
long mycount = 0;
int gave_way = 0;   /* set by nothing: the other team's arm was to give way */
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
    if (mycount == 1000) {
        while (gave_way == 0) { }
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%.2f\n\r", printtheta1motor * 180 / PI);
}
