/* Test lab, Gen A style: on its first call prints one line of LINE_CHARS characters, the line end
 * included (a debug dump of a long array, say), then its call count every 100 ms. Gen A's
 * serial_printf formats into a 2048-byte buffer: 2047 characters and the NUL fit, 2048 do not.
 * The tests set LINE_CHARS. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

#define LINE_CHARS 2047

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
char dump[LINE_CHARS - 1];

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 100) == 0) {
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void printing(void)
{
    int i;
    if (mycount == 1) {
        for (i = 0; i < LINE_CHARS - 2; i++) {
            dump[i] = (char)('a' + i % 26);
        }
        dump[LINE_CHARS - 2] = 0;
        serial_printf(&SerialA, "%s\n\r", dump);
    } else {
        serial_printf(&SerialA, "call %ld\n\r", mycount - 1);
    }
}
