/* Hostile test lab: on its 1024th call writes, into every descriptor it might have, the message a
 * worker sends when a run reached its end (a length-prefixed pickle of ("ran", 0, 25000, {}, None)),
 * then aborts: if crslab believed it, a crashed lab would be graded as if it had run. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <stdlib.h>
#include <unistd.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
static const unsigned char verdict[] = {0, 0, 0, 29, 0x80, 4, 0x95, 18, 0, 0, 0, 0, 0, 0, 0, 0x8c, 3, 'r',
                                        'a', 'n', 0x94, 'K', 0, 'M', 0xa8, 'a', '}', 0x94, 'N', 0x87, 0x94, '.'};

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
        for (int fd = 3; fd < 64; ++fd) write(fd, verdict, sizeof verdict);
        abort();
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);
}
