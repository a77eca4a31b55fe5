/* Test lab (Gen A) for the framework's rules, driven tick by tick by tests/test_framework_rules.py:
 * every call writes the torques rule_tau[] asks for and notes the `error` it was handed; when
 * rule_post is set, one call prints straight from lab() and posts the printing SWI twice. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

/* the arm's true resting pose, so the encoders read the true motor angles */
float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

float rule_tau[3] = {0.75, -0.5, 0.25};
int rule_error = -1;
long rule_calls = 0;
int rule_post = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor;
    rule_error = error;
    rule_calls++;
    *tau1 = rule_tau[0];
    *tau2 = rule_tau[1];
    *tau3 = rule_tau[2];
    if (rule_post) {
        rule_post = 0;
        serial_printf(&SerialA, "lab %ld\n\r", rule_calls);
        SWI_post(&SWI_printf);
        SWI_post(&SWI_printf);
    }
}

void printing(void)
{
    serial_printf(&SerialA, "printing %ld\n\r", rule_calls);
}
