/* Test lab: Lab 1 with the student's own kinematics (math.h only). Every 500 ms it prints the
 * motor angles (deg), the forward-kinematics x y z (in) and the motor angles (deg) its elbow-up
 * inverse kinematics finds for that x y z. Link lengths and base height are 10 in. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

long mycount = 0;

#pragma DATA_SECTION(whattoprint, ".my_vars")
float whattoprint = 0.0;

float printtheta1motor = 0, printtheta2motor = 0, printtheta3motor = 0;
float x = 0, y = 0, z = 0;
float IKtheta1motor = 0, IKtheta2motor = 0, IKtheta3motor = 0;

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;

    if ((mycount % 500) == 0) {
        float r_in, s_in, D, th1DH, th2DH, th3DH;
        printtheta1motor = theta1motor;
        printtheta2motor = theta2motor;
        printtheta3motor = theta3motor;

        /* forward kinematics in motor angles */
        x = 10 * cos(theta1motor) * (cos(theta3motor) + sin(theta2motor));
        y = 10 * sin(theta1motor) * (cos(theta3motor) + sin(theta2motor));
        z = 10 * (1 + cos(theta2motor) - sin(theta3motor));

        /* inverse kinematics, elbow up: planar two-link in (r, -s) with s the height above
         * the shoulder */
        th1DH = atan2(y, x);
        r_in = sqrt(x * x + y * y);
        s_in = z - 10;
        D = (r_in * r_in + s_in * s_in - 200) / 200;
        if (D > 1) D = 1;
        if (D < -1) D = -1;
        th3DH = acos(D);
        th2DH = atan2(-s_in, r_in) - atan2(10 * sin(th3DH), 10 + 10 * cos(th3DH));
        IKtheta1motor = th1DH;
        IKtheta2motor = th2DH + PI / 2;
        IKtheta3motor = th3DH + th2DH;

        SWI_post(&SWI_printf);
        GpioDataRegs.GPBTOGGLE.bit.GPIO34 = 1;
    }

    Simulink_PlotVar1 = theta1motor;
    Simulink_PlotVar2 = theta2motor;
    Simulink_PlotVar3 = theta3motor;
    Simulink_PlotVar4 = z;

    mycount++;
}

void printing(void)
{
    if (whattoprint > 0.5) {
        serial_printf(&SerialA, "I love robotics\n\r");
    } else {
        serial_printf(&SerialA, "%.2f %.2f %.2f\n\r", printtheta1motor * 180 / PI,
                      printtheta2motor * 180 / PI, printtheta3motor * 180 / PI);
        serial_printf(&SerialA, "%.2f %.2f %.2f\n\r", x, y, z);
        serial_printf(&SerialA, "%.2f %.2f %.2f\n\r", IKtheta1motor * 180 / PI,
                      IKtheta2motor * 180 / PI, IKtheta3motor * 180 / PI);
    }
}
