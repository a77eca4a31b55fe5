/* crslab's default lab: Lab 1 (kinematics), written the way a Gen A "CRSRobot" lab file is.
 *
 * Every 1 ms the framework calls lab() with the three motor angles (rad). Every 500 calls this
 * lab prints three lines to Tera Term: the motor angles (deg), the end-effector x y z (in) from
 * forward kinematics, and the motor angles (deg) that elbow-up inverse kinematics finds for that
 * x y z, which must equal the first line. It uses crslab's C kinematics (crs_arm.h) rather than
 * its own copy of the formulas. Set whattoprint to 1 (a watched variable) to print a greeting
 * instead. Torques stay zero: the arm is moved by hand. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include "crs_arm.h"

/* The motor angles of the resting pose the encoders were zeroed in (found in Lab 1). */
float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

long mycount = 0;

#pragma DATA_SECTION(whattoprint, ".my_vars")
float whattoprint = 0.0;

#pragma DATA_SECTION(theta1array, ".my_arrs")
float theta1array[100];
#pragma DATA_SECTION(theta2array, ".my_arrs")
float theta2array[100];
long arrayindex = 0;

/* what printing() prints, captured in lab() */
float printtheta1motor = 0, printtheta2motor = 0, printtheta3motor = 0;
float x_in = 0, y_in = 0, z_in = 0;
float ik_theta1motor = 0, ik_theta2motor = 0, ik_theta3motor = 0;
int ik_status = 0;

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;

    /* save past states every 50 ms */
    if ((mycount % 50) == 0) {
        theta1array[arrayindex] = theta1motor;
        theta2array[arrayindex] = theta2motor;
        if (arrayindex >= 99) {
            arrayindex = 0;
        } else {
            arrayindex++;
        }
    }

    if ((mycount % 500) == 0) {
        if (whattoprint < 0.5) {
            const double motor_rad[3] = {theta1motor, theta2motor, theta3motor};
            double xyz[3], ik_rad[3];
            crs_fk_motor(motor_rad, xyz);
            ik_status = (int)crs_ik_motor(xyz, 1, ik_rad);
            printtheta1motor = theta1motor;
            printtheta2motor = theta2motor;
            printtheta3motor = theta3motor;
            x_in = xyz[0];
            y_in = xyz[1];
            z_in = xyz[2];
            ik_theta1motor = ik_rad[0];
            ik_theta2motor = ik_rad[1];
            ik_theta3motor = ik_rad[2];
        }
        SWI_post(&SWI_printf);                 /* printing() runs after lab() returns */
        GpioDataRegs.GPBTOGGLE.bit.GPIO34 = 1; /* blink the LED on the control card */
        GpioDataRegs.GPBTOGGLE.bit.GPIO60 = 1; /* blink the LED on the e-stop box */
    }

    Simulink_PlotVar1 = theta1motor;
    Simulink_PlotVar2 = theta2motor;
    Simulink_PlotVar3 = theta3motor;
    Simulink_PlotVar4 = z_in;

    mycount++;
}

void printing(void)
{
    if (whattoprint > 0.5) {
        serial_printf(&SerialA, "I love robotics\n\r");
    } else {
        serial_printf(&SerialA, "%.2f %.2f %.2f\n\r", printtheta1motor * 180 / PI,
                      printtheta2motor * 180 / PI, printtheta3motor * 180 / PI);
        serial_printf(&SerialA, "%.2f %.2f %.2f\n\r", x_in, y_in, z_in);
        if (ik_status == 0) {
            serial_printf(&SerialA, "%.2f %.2f %.2f\n\r", ik_theta1motor * 180 / PI,
                          ik_theta2motor * 180 / PI, ik_theta3motor * 180 / PI);
        } else {
            serial_printf(&SerialA, "IK: no solution\n\r");
        }
    }
}
