/* Hostile test lab: on its 1024th call makes every descriptor it has send SIGIO to the process
 * that started it (fcntl F_SETOWN, then O_ASYNC) and writes to each: on a kernel whose Landlock
 * does not scope signals, the signal would kill crslab grade. */
#define _GNU_SOURCE /* F_SETOWN, O_ASYNC */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <fcntl.h>
#include <unistd.h>

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
        for (int fd = 0; fd < 64; ++fd) {
            if (fcntl(fd, F_SETOWN, getppid()) == 0) {
                fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_ASYNC);
                write(fd, "x", 1);
            }
        }
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);
}
