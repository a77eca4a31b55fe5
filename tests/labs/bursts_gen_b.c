/* Test lab, Gen B ("me446 starter") style: three bursts of four 60-character lines straight from
 * lab(), at its calls 0, 3 and 2000 (t = 4.100, 4.103 and 6.100 s). 240 characters at once are
 * more than the board's 136-byte transmit ring (and 16-byte FIFO) hold, and the second burst
 * comes before the first has left: characters are dropped as on the board. */
#include "math.h"
#include "F28335Serial.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    int line;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount == 0 || mycount == 3 || mycount == 2000) {
        for (line = 1; line <= 4; line++) {
            /* 60 characters: 58 of text and the line end */
            serial_printf(&SerialA, "burst at call %4ld, line %d: %-30s\n\r", mycount, line,
                          "the quick brown fox jumps");
        }
    }
    mycount++;
}
