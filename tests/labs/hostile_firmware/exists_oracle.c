/* Hostile test lab: asks the compiler whether files outside its folder exist (SECRET_PATH, which
 * the tests make, and a path nobody has) and prints the answers. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

#if __has_include("SECRET_PATH")
#define SECRET_EXISTS 1
#else
#define SECRET_EXISTS 0
#endif
#if __has_include("/no/such/folder/nothing.h")
#define NOTHING_EXISTS 1
#else
#define NOTHING_EXISTS 0
#endif

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
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f exists %d %d\n\r", mycount, 0.0, SECRET_EXISTS,
                  NOTHING_EXISTS);
}
