/* Test lab: an array whose size the source's text and the compiler disagree on. A text reading
 * keeps the last #define of NSAMPLES (400); the compiler, on a host where HOST_BUILD is not
 * defined, takes the first (4). A host tool must never read or write past the 4 floats that
 * exist. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

#ifndef HOST_BUILD
#define NSAMPLES 4
#else
#define NSAMPLES 400
#endif

#pragma DATA_SECTION(samples, ".my_arrs")
float samples[NSAMPLES] = {1.5, 2.5, 3.5, 4.5};
#pragma DATA_SECTION(guard, ".my_arrs")
float guard = 7.0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
}

void printing(void) {}
