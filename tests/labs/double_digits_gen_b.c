/* Test lab, Gen B ("me446 starter") style: arithmetic in double, which is a 32-bit float on the C28x
 * (COFF ABI): a third, a sum of a thousand tenths, a product and a square root, printed with more
 * digits than a float holds, once, on the first call. */
#include "math.h"
#include "F28335Serial.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;
long mycount = 0;
double third = 0;
double tenths = 0;
double product = 0;
double root = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    int i;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount == 0) {
        third = 1.0 / 3.0;
        tenths = 0;
        for (i = 0; i < 1000; i++) {
            tenths = tenths + 0.1;
        }
        product = 16777217.0 * 3.0;
        root = sqrt(2.0);
        UARTprint = 1;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%.10f %.6f %.1f %.10f\n\r", third, tenths, product, root);
}
