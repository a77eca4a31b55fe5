/* Hostile test lab: on its 1024th call writes a message of its own into every socket it has,
 * which includes the pipe to crslab: a pickle that, if crslab unpickled it, would run a shell
 * command creating the file TARGET_PATH (the tests write a path outside the run there). */
#define _POSIX_C_SOURCE 200809L /* for fstat() and S_ISSOCK under -std=c11 */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
static const char target_path[] = "TARGET_PATH";
char message[600];

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
        char *body = message + 4;
        int n = snprintf(body, sizeof message - 4, "cos\nsystem\n(S'touch %s'\ntR.",
                         target_path);
        message[0] = 0; /* the pipe's framing: a 4-byte big-endian length */
        message[1] = 0;
        message[2] = (char)(n >> 8);
        message[3] = (char)(n & 0xff);
        for (int fd = 3; fd < 64; ++fd) {
            struct stat st;
            if (fstat(fd, &st) == 0 && S_ISSOCK(st.st_mode)) {
                write(fd, message, (size_t)n + 4);
            }
        }
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);
}
