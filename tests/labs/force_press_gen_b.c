/* Test lab in the style of the final project's egg press: task-space impedance with x and y
 * stiff around the point where lab() is first called, z free, and a pressing force Fpress (N)
 * straight down fed forward through the Jacobian's transpose:
 *     F = [KPxy (xd - x) - KDxy xdot, KPxy (yd - y) - KDxy ydot, -KDz zdot - Fpress]   (N, m)
 *     tau = J^T F / 6 + gravity of the course's dynamic model                          (units)
 * (G = [-p4 g sin th2M, -p5 g cos th3M], 6 N.m per command unit). No friction compensation: the
 * press begins with the arm at rest. Velocities are backward differences averaged over three
 * samples. Its offsets are the motor angles of the egg's height and reach (0.47, 0.80 rad), where
 * the test starts the arm. Prints x y z (mm) every 500 ms. A Gen B ("me446 starter") file. */
#include "math.h"
#include "F28335Serial.h"

#define PI 3.1415926535897932384626433832795
#define GRAV 9.81

float offset_Enc2_rad = 0.471;
float offset_Enc3_rad = 0.804;
int UARTprint = 0;

#pragma DATA_SECTION(Fpress, ".my_vars")
float Fpress = 0.0;        /* N, straight down */
#pragma DATA_SECTION(KPxy, ".my_vars")
float KPxy = 5000.0;       /* N/m */
float KDxy = 100.0;        /* N s/m */
float KDz = 20.0;          /* N s/m */
float p4 = 0.0753, p5 = 0.0298;   /* the course's gravity parameters, command units */

long mycount = 0;
float xd = 0, yd = 0;
float p_old[3] = {0, 0, 0};
float v_old1[3] = {0, 0, 0}, v_old2[3] = {0, 0, 0};
float printxyz[3] = {0, 0, 0};

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    float c1 = cos(theta1motor), s1 = sin(theta1motor);
    float c2 = cos(theta2motor), s2 = sin(theta2motor);
    float c3 = cos(theta3motor), s3 = sin(theta3motor);
    const float L = 0.254;   /* each link, m */
    float J11 = -L * s1 * (c3 + s2), J12 = L * c1 * c2, J13 = -L * c1 * s3;
    float J21 = L * c1 * (c3 + s2),  J22 = L * s1 * c2, J23 = -L * s1 * s3;
    float J31 = 0,                   J32 = -L * s2,     J33 = -L * c3;
    float p[3], v[3], F[3];
    int j;

    p[0] = L * c1 * (c3 + s2);
    p[1] = L * s1 * (c3 + s2);
    p[2] = L * (1 + c2 - s3);
    if (mycount == 0) {
        xd = p[0];
        yd = p[1];
        for (j = 0; j < 3; j++) {
            p_old[j] = p[j];
        }
    }
    for (j = 0; j < 3; j++) {
        v[j] = (p[j] - p_old[j]) / 0.001;
        v[j] = (v[j] + v_old1[j] + v_old2[j]) / 3.0;
        v_old2[j] = v_old1[j];
        v_old1[j] = v[j];
        p_old[j] = p[j];
    }
    F[0] = KPxy * (xd - p[0]) - KDxy * v[0];
    F[1] = KPxy * (yd - p[1]) - KDxy * v[1];
    F[2] = -KDz * v[2] - Fpress;

    *tau1 = (J11 * F[0] + J21 * F[1] + J31 * F[2]) / 6.0;
    *tau2 = (J12 * F[0] + J22 * F[1] + J32 * F[2]) / 6.0 - p4 * GRAV * s2;
    *tau3 = (J13 * F[0] + J23 * F[1] + J33 * F[2]) / 6.0 - p5 * GRAV * c3;

    if ((mycount % 500) == 0) {
        for (j = 0; j < 3; j++) {
            printxyz[j] = 1000 * p[j];
        }
        UARTprint = 1;
    }
    Simulink_PlotVar1 = p[0];
    Simulink_PlotVar2 = p[1];
    Simulink_PlotVar3 = p[2];
    Simulink_PlotVar4 = Fpress;
    mycount++;
    (void)error;
}

void printing(void)
{
    serial_printf(&SerialA, "%.2f %.2f %.2f\n\r", printxyz[0], printxyz[1], printxyz[2]);
}
