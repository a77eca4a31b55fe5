/* Test lab, Gen A style, with the quirks real files have: globals named like libc and libm
 * symbols (gamma, y0, j1, step, index, time, error), the template's DATA_SECTION pragmas, %ld
 * and %s formats, and a serial_printf straight from lab(). */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

long mycount = 0;
float gamma = 2.5;   /* glibc's gamma() in GNU modes */
float y0 = 1.0;      /* glibc's Bessel y0() */
float j1 = 3.0;      /* glibc's Bessel j1() */
long step = 0;       /* a common libc-ish name */
int index = 7;       /* strings.h index() */
long time = 0;       /* time() */
int error = 0;       /* error() of error.h */

#pragma DATA_SECTION(whattoprint, ".my_vars")
float whattoprint = 0.0;

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int err)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    error = err;
    time++;
    step += index;
    if (mycount == 0) {
        serial_printf(&SerialA, "hello from lab() %s\n\r", "gen A");
    }
    if ((mycount % 1000) == 0) {
        SWI_post(&SWI_printf);
        SWI_post(&SWI_printf); /* two posts in one tick: printing() runs once */
    }
    Simulink_PlotVar1 = theta1motor;
    Simulink_PlotVar2 = theta2motor;
    Simulink_PlotVar3 = theta3motor;
    Simulink_PlotVar4 = gamma;
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld time %ld step %ld gamma %.2f y0 %.1f j1 %.1f\n\r", mycount,
                  time, step, gamma, y0, j1);
}
