/* Test lab: line 9 uses a gain the student never declared. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = Kp_gain * theta1motor;
    *tau2 = 0;
    *tau3 = 0;
}

void printing(void) {}
