/* Hostile test lab: on its 1024th call reads the resource limits of the process that started it
 * (crslab): what a grader allows, an oracle about the machine. */
#define _GNU_SOURCE /* prlimit */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <sys/resource.h>
#include <unistd.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
long learned = -1;

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
        struct rlimit lim;
        learned = prlimit(getppid(), RLIMIT_AS, NULL, &lim) == 0 ? (long)(lim.rlim_cur >> 20) : -2;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);
    if (learned != -1) serial_printf(&SerialA, "limit %ld\n\r", learned);
}
