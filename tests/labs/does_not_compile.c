/* Test lab: a missing semicolon on line 9, as students make them. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0
    *tau2 = 0;
    *tau3 = 0;
}

void printing(void) {}
