/* Test lab in the style of the course's Lab 1 template (Gen A, "CRSRobot"): two arrays the MATLAB
 * scripts read (.my_arrs) are filled one sample per call, and the index is reset only once it has
 * passed 99, so the 101st sample is stored one past each array's end. The samples are numbers of
 * their own (the call's count) so that what is printed can be worked out from the map by hand:
 * on the board theta2array[100] is the first word of theta3array, the next variable of .my_arrs,
 * and theta3array[100] is past the section's end; x, an ordinary global (.ebss), is far away. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;

#pragma DATA_SECTION(whattoprint, ".my_vars")
float whattoprint = 0.0;
#pragma DATA_SECTION(theta2array, ".my_arrs")
float theta2array[100];
float x = 0, y = 0, z = 0;   /* the end effector, inches */
#pragma DATA_SECTION(theta3array, ".my_arrs")
float theta3array[100];
long arrayindex = 0;
float printx = 0, printfirst = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    x = 20.0;
    y = 0.0;
    z = 10.0;
    theta2array[arrayindex] = mycount;
    theta3array[arrayindex] = 1000 + mycount;
    if (arrayindex >= 100) {
        arrayindex = 0;
    } else {
        arrayindex++;
    }
    if (mycount == 0 || mycount == 100 || mycount == 101) {
        printx = x;
        printfirst = theta3array[0];
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld x %.2f theta3array[0] %.1f\n\r", mycount, printx, printfirst);
}
