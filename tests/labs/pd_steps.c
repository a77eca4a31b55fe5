/* Test lab in the style of Lab 2: PD control of the three motor angles, stepping every 1 s
 * between 0 and pi/6 rad; the velocity is a backward difference averaged over three samples.
 * Prints the three motor angles (rad) every 100 ms. A Gen B ("me446 starter") file. */
#include "math.h"
#include "F28335Serial.h"

#define PI 3.1415926535897932384626433832795
#define TWOPI 6.283185307179586476925286766559
#define HALFPI 1.5707963267948966192313216916398
#define GRAV 9.81

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;

#pragma DATA_SECTION(Kp, ".my_vars")
float Kp = 60.0;
#pragma DATA_SECTION(Kd, ".my_vars")
float Kd = 2.2;

long mycount = 0;
float theta_old[3] = {0, 0, 0};
float omega_old1[3] = {0, 0, 0};
float omega_old2[3] = {0, 0, 0};
float printtheta[3] = {0, 0, 0};

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    const float theta[3] = {theta1motor, theta2motor, theta3motor};
    float tau[3];
    const float desired = ((mycount / 1000) % 2 == 0) ? 0.0f : (float)(PI / 6.0);
    int j;
    for (j = 0; j < 3; j++) {
        float omega = (theta[j] - theta_old[j]) / 0.001f;
        omega = (omega + omega_old1[j] + omega_old2[j]) / 3.0f;
        tau[j] = Kp * (desired - theta[j]) - Kd * omega;
        theta_old[j] = theta[j];
        omega_old2[j] = omega_old1[j];
        omega_old1[j] = omega;
    }
    *tau1 = tau[0];
    *tau2 = tau[1];
    *tau3 = tau[2];
    if ((mycount % 100) == 0) {
        printtheta[0] = theta1motor;
        printtheta[1] = theta2motor;
        printtheta[2] = theta3motor;
        UARTprint = 1;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%.3f %.3f %.3f\n\r", printtheta[0], printtheta[1], printtheta[2]);
}
