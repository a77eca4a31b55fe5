/* Test lab (Gen A): the three torques are watched variables (tau_units, command units), applied
 * from the first call on; nothing printed. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

#pragma DATA_SECTION(tau_units, ".my_arrs")
float tau_units[3] = {0, 0, 0};

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = tau_units[0];
    *tau2 = tau_units[1];
    *tau3 = tau_units[2];
    (void)theta1motor;
    (void)theta2motor;
    (void)theta3motor;
    (void)error;
}

void printing(void) {}
