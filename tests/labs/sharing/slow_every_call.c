/* Test lab (a worker its runs share): every call sums a series of sum_each_call terms first, some
 * 9 million WebAssembly instructions, 60 ms of the board's 1 ms tick; prints its count every 500
 * calls. A lab that costs more than real time, but returns from every call. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
long sum_each_call = 360000;
volatile long series = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    long i;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    for (i = 0; i < sum_each_call; i++) series += i;
    if ((mycount % 500) == 0) SWI_post(&SWI_printf);
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld\n\r", mycount);
}
