/* Test lab: prints 2 kB every millisecond (two 1000-character lines), far more than the serial
 * line sends (11.52 characters per ms): most of it never fits the transmit ring. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <stdlib.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
char block[999];
int filled = 0;
static void fill(void)
{
    for (int i = 0; i < 998; ++i) block[i] = (char)(33 + i % 90);
    block[998] = 0;
    filled = 1;
}

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0) {
        SWI_post(&SWI_printf);
    }
    if (!filled) fill();
    serial_printf(&SerialA, "%s\n\r", block);
    serial_printf(&SerialA, "%s\n\r", block);
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);

}
