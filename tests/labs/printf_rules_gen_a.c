/* Test lab, Gen A style: prints the same nine values with each format the course's labs use, so
 * the small printf's rules show (truncation, %f's five decimals, widths, flags), then integers,
 * hex, binary, text and a conversion the small printf does not know. Prints once, on the first
 * call; torques stay zero. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
float values[9] = {1.41, 87.06, -1.99, 29.82, 0.1, 123.456, -0.004, 2.5, 0.001};
int small = -2;
int big = 70000;      /* 16 bits on the board: prints its low 16 bits */
long counter = 100000;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount == 0) {
        SWI_post(&SWI_printf);
    }
    mycount++;
}

void printing(void)
{
    int i;
    for (i = 0; i < 9; i++) {
        serial_printf(&SerialA, "%.2f|%f|%6.2f|%-8.3f|%+.1f|%07.2f|%.0f\n\r", values[i], values[i],
                      values[i], values[i], values[i], values[i], values[i]);
    }
    serial_printf(&SerialA, "%d %d %ld %5d|%-5d|%05d|%+d\n\r", small, big, counter, 42, 42, -42, 7);
    serial_printf(&SerialA, "%x %x %b %b %lx\n\r", 255, small, 5, small, counter);
    serial_printf(&SerialA, "%c %s %6s|%-6s| 100%% %u\n\r", 'A', "lab", "lab", "lab", 5);
}
