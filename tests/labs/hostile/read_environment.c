/* Hostile test lab: on its 1024th call prints every environment variable crslab was started
 * with on the serial port (a teaching assistant's tokens and paths would land in the grading
 * report). A lab runs with an empty environment, so it prints nothing more. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <stdlib.h>

extern char **environ;

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
long next_variable = -1; /* -1: not yet asked */

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0 || next_variable >= 0) {
        SWI_post(&SWI_printf);
    }
    if (mycount == 1023) {
        next_variable = 0;
    }
    mycount++;
}

void printing(void)
{
    if (next_variable < 0) {
        serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);
    } else if (environ != NULL && environ[next_variable] != NULL) {
        serial_printf(&SerialA, "%s\n\r", environ[next_variable]);
        next_variable++;
    }
}
