/* Test lab, Gen B ("me446 starter") style: prints the same nine values with the formats the
 * course's labs use through TI's vsprintf, which rounds; then integers (16-bit int, 32-bit long),
 * hex and text. One line every 20 ms (Gen B's 136-byte transmit ring could not take them all at
 * once); torques stay zero. */
#include "math.h"
#include "F28335Serial.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;
long mycount = 0;
float values[9] = {1.41, 87.06, -1.99, 29.82, 0.1, 123.456, -0.004, 2.5, 0.001};
int small = -2;
int big = 70000;      /* 16 bits on the board: prints its low 16 bits */
long counter = 100000;
int line = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount % 20 == 0 && line < 12) {
        UARTprint = 1;
    }
    mycount++;
}

void printing(void)
{
    if (line < 9) {
        serial_printf(&SerialA, "%.2f|%f|%6.2f|%-8.3f|%+.1f|%07.2f|%.0f\n\r", values[line], values[line],
                      values[line], values[line], values[line], values[line], values[line]);
    } else if (line == 9) {
        serial_printf(&SerialA, "%d %d %ld %5d|%-5d|%05d|%+d\n\r", small, big, counter, 42, 42, -42, 7);
    } else if (line == 10) {
        serial_printf(&SerialA, "%x %x %lx %u\n\r", 255, small, counter, small);
    } else {
        serial_printf(&SerialA, "%c %s %6s|%-6s| 100%%\n\r", 'A', "lab", "lab", "lab");
    }
    line++;
}
