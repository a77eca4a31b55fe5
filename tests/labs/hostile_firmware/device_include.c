/* Hostile test lab: includes a device that never ends (its compiler would read forever). */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include "/dev/urandom"

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error) {}
