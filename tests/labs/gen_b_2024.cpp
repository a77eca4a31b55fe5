/* Test lab, Gen B ("me446 starter", 2024) style, kept in a .cpp file that holds C: it defines
 * PI and friends itself, prints through UARTprint, and has the 2024 main() that calls
 * mains_code(). */
#include "math.h"
#include "F28335Serial.h"
#include <stdbool.h>

#define PI          3.1415926535897932384626433832795
#define TWOPI       6.283185307179586476925286766559
#define HALFPI      1.5707963267948966192313216916398
#define GRAV        9.81

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

int UARTprint = 0;
long mycount = 0;
bool started = false;

float printtheta1motor = 0;
float printtheta2motor = 0;
float printtheta3motor = 0;

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

void main(void)
{
    mains_code();
}

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    started = true;
    if ((mycount % 500) == 0) {
        printtheta1motor = theta1motor;
        printtheta2motor = theta2motor;
        printtheta3motor = theta3motor;
        UARTprint = 1;
        GpioDataRegs.GPBTOGGLE.bit.GPIO34 = 1;
        GpioDataRegs.GPBTOGGLE.bit.GPIO60 = 1;
    }
    Simulink_PlotVar1 = theta1motor;
    Simulink_PlotVar2 = theta2motor;
    Simulink_PlotVar3 = theta3motor;
    Simulink_PlotVar4 = (float)error;
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%.2f %.2f %.2f   %d\n\r", printtheta1motor * 180 / PI,
                  printtheta2motor * 180 / PI, printtheta3motor * 180 / PI, (int)started);
}
