/* Test lab (Gen B) for the framework's print trigger, driven tick by tick by
 * tests/test_framework_rules.py: when rule_post is set, one call prints straight from lab() and
 * sets UARTprint; the torques stay 0. */
#include "math.h"
#include "F28335Serial.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;

long rule_calls = 0;
int rule_post = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
    rule_calls++;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (rule_post) {
        rule_post = 0;
        serial_printf(&SerialA, "lab %ld\n\r", rule_calls);
        UARTprint = 1;
    }
}

void printing(void)
{
    serial_printf(&SerialA, "printing %ld UARTprint %d\n\r", rule_calls, UARTprint);
}
