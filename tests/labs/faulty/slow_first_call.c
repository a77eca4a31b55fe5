/* Test lab: its first lab() call takes long, then every call is quick. SPIN_FIRST_S: the first
 * call spins that much of its CPU time; SLEEP_FIRST_S: it sleeps that long instead (a lab that
 * waits on nothing). A call is hung for the time it takes itself, not for the cores a loaded
 * machine gave others meanwhile. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include <time.h>

#define SPIN_FIRST_S 0.4
#define SLEEP_FIRST_S 0.0

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
volatile double sink = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount == 0) {
        clock_t start = clock();
        while (clock() - start < (clock_t)(SPIN_FIRST_S * CLOCKS_PER_SEC)) {
            sink += sin(theta1motor + sink);
        }
        struct timespec nap = {(time_t)SLEEP_FIRST_S,
                               (long)((SLEEP_FIRST_S - (time_t)SLEEP_FIRST_S) * 1e9)};
        nanosleep(&nap, NULL);
    }
    mycount++;
}

void printing(void) {}
