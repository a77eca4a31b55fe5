/* Hostile test lab: on its 1024th call opens a file whose name holds terminal escape sequences (a
 * green "pass", then erase-line), a right-to-left override and the non-character U+FFFE: the
 * refusal quotes the name, and every report must show those bytes, not obey them. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <stdio.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0) {
        SWI_post(&SWI_printf);
    }
    if (mycount == 1023) {
        fopen("/tmp/\x1b[2K\r\x1b[32mpass\x1b[0m\xe2\x80\xae\xef\xbf\xbe", "r");
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);
}
