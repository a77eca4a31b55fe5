/* @LAB@: a starting point written the way a Gen A "CRSRobot" lab file is.
 *
 * Every 1 ms the framework calls lab() with the three motor angles (rad); whatever you write into
 * *tau1..*tau3 (command units, clamped to +-5) drives the motors. Every 500 calls (0.5 s) lab()
 * posts SWI_printf, and printing() then prints the motor angles (deg) to Tera Term. Set the
 * watched variable whattoprint to 1 to print a greeting instead. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

/* The motor angles of the resting pose the encoders are zeroed in: find your arm's in Lab 1. */
float offset_Enc2_rad = -0.37;
float offset_Enc3_rad = 0.27;

long mycount = 0;

#pragma DATA_SECTION(whattoprint, ".my_vars")
float whattoprint = 0.0;

#pragma DATA_SECTION(theta1array, ".my_arrs")
float theta1array[100];
#pragma DATA_SECTION(theta2array, ".my_arrs")
float theta2array[100];
long arrayindex = 0;

/* what printing() prints, captured in lab() */
float printtheta1motor = 0;
float printtheta2motor = 0;
float printtheta3motor = 0;

/* the four signals the course's Simulink model plots */
float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2, float *tau3,
         int error) {

    /* your controller: torques in command units (+-5 at most) */
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;

    /* keep the last 100 samples, one every 50 ms, for the MATLAB tools to read */
    if ((mycount % 50) == 0) {
        theta1array[arrayindex] = theta1motor;
        theta2array[arrayindex] = theta2motor;
        arrayindex = (arrayindex + 1) % 100;
    }

    if ((mycount % 500) == 0) {
        if (whattoprint > 0.5) {
            serial_printf(&SerialA, "Hello from lab() at count %ld\n\r", mycount);
        } else {
            printtheta1motor = theta1motor;
            printtheta2motor = theta2motor;
            printtheta3motor = theta3motor;
            SWI_post(&SWI_printf);   /* printing() runs once lab() returns */
        }
        GpioDataRegs.GPBTOGGLE.bit.GPIO34 = 1;   /* blink the control card's LED */
        GpioDataRegs.GPBTOGGLE.bit.GPIO60 = 1;   /* and the e-stop box's */
    }

    Simulink_PlotVar1 = theta1motor;
    Simulink_PlotVar2 = theta2motor;
    Simulink_PlotVar3 = theta3motor;
    Simulink_PlotVar4 = 0;

    mycount++;
}

void printing(void) {
    serial_printf(&SerialA, "%.2f %.2f %.2f\n\r", printtheta1motor * 180 / PI, printtheta2motor * 180 / PI,
                  printtheta3motor * 180 / PI);
}
