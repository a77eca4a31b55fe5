/* Test lab (a worker its runs share): every call writes nothing to the console, writes_each_call
 * times, each time with 65,000 empty iovecs the board must walk (a few instructions of the lab's,
 * 65,000 steps of the board's); prints its count every 500 calls. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
long writes_each_call = 100;
/* The firmware's C library's calloc and writev, declared here with their wasm32 widths (32-bit
 * counts and sizes: longs with the C28x's widths), which no header a lab can include has: 65,000
 * empty iovecs (two 32-bit zeros each, 520,000 bytes, more than one C28x array may hold) */
void *calloc(long count, long size);
long writev(long fd, const void *iov, long iovcnt);
static void *nothing;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    long i;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (nothing == 0) nothing = calloc(65000L, 8L);
    for (i = 0; i < writes_each_call; i++) writev(1, nothing, 65000);
    if ((mycount % 500) == 0) SWI_post(&SWI_printf);
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld\n\r", mycount);
}
