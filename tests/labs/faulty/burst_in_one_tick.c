/* Test lab: at its first call prints 5000 lines of 1 kB (5 MB within one tick, far more than the
 * board's transmit ring holds), then a short line every 100 calls. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
char row[1023];

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount == 0) {
        for (int i = 0; i < 1022; ++i) row[i] = (char)('a' + i % 26);
        row[1022] = 0;
        for (int n = 0; n < 5000; ++n) {
            serial_printf(&SerialA, "%s\n\r", row); /* 1024 bytes each */
        }
    } else if ((mycount % 100) == 0) {
        serial_printf(&SerialA, "after %ld\n\r", mycount);
    }
    mycount++;
}

void printing(void)
{
}
