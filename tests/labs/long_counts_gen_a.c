/* Test lab in the style of Lab 1, Gen A, that counts in `long` (32 bits on the board): the motor
 * angles as encoder counts (288 000 per motor revolution), the calls' running sum of joint 3's counts
 * and the milliseconds since the first call times 1000 (microseconds); printed with %ld every 500
 * calls. Every value stays within 32 bits, so the board, the WebAssembly build and a native build
 * (where long is 64 bits) print the same. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
long counts[3];
long sum3 = 0;
long micros = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    counts[0] = (long)(theta1motor * 144000 / PI);
    counts[1] = (long)(theta2motor * 144000 / PI);
    counts[2] = (long)(theta3motor * 144000 / PI);
    sum3 += counts[2];
    micros = mycount * 1000L;
    if ((mycount % 500) == 0) {
        SWI_post(&SWI_printf);
    }
    mycount++;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
}

void printing(void)
{
    serial_printf(&SerialA, "%ld us: counts %ld %ld %ld, sum %ld\n\r", micros, counts[0], counts[1],
                  counts[2], sum3);
}
