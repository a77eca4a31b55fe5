/* Hostile test lab: on its 1024th call overwrites every byte of its memory it can reach (its
 * stack, its data, the framework's variables in it, its heap) with 0x41, and returns. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <stdint.h>
#include <stdlib.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;

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
        volatile unsigned char *p = (volatile unsigned char *)1;
        size_t end = (size_t)__builtin_wasm_memory_size(0) * 65536;
        for (size_t i = 0; i + 1 < end; ++i) p[i] = 0x41;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);
}
