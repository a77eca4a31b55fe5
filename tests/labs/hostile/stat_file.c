/* Hostile test lab: on its 1024th call asks whether the file SECRET_PATH exists, how large it is
 * and when it changed (no read, but an oracle all the same) and prints what it learned: with
 * fstatat's AT_EMPTY_PATH flag set, as fstat() sets it, though its path is not empty. */
#define _GNU_SOURCE /* AT_EMPTY_PATH */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <fcntl.h>
#include <sys/stat.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
static const char secret_path[] = "SECRET_PATH";
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
        struct stat st;
        learned = fstatat(AT_FDCWD, secret_path, &st, AT_EMPTY_PATH) == 0 ? (long)st.st_size : -2;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);
    if (learned != -1) serial_printf(&SerialA, "size %ld\n\r", learned);
}
