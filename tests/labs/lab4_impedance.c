/* Test lab in the style of Lab 4: task-space impedance control in a rotated frame N. The end
 * effector is held at the point where lab() is first called:
 *     F = R Kp R^T (xd - x) - R Kd R^T xdot      (N, world frame; x in m)
 *     tau = J^T F                                 (N.m on the motor angles)
 * with R = Rz(thz) Rx(thx) Ry(thy) (rad) and the diagonal gains KPx KPy KPz (N/m) and
 * KDx KDy KDz (N.s/m) along N's axes, plus the gravity of the course's dynamic model
 * (G = [-p4 g sin th2M, -p5 g cos th3M] command units). The motors give 6 N.m per command
 * unit. Velocities are backward differences averaged over three samples. Prints x y z (in)
 * every 500 ms. A Gen B ("me446 starter") file. */
#include "math.h"
#include "F28335Serial.h"

#define PI 3.1415926535897932384626433832795
#define GRAV 9.81
#define NM_PER_UNIT 6.0

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;

/* stiffness and damping along the axes of frame N */
#pragma DATA_SECTION(KPx, ".my_vars")
float KPx = 300.0;
#pragma DATA_SECTION(KPy, ".my_vars")
float KPy = 10000.0;
#pragma DATA_SECTION(KPz, ".my_vars")
float KPz = 10000.0;
#pragma DATA_SECTION(KDx, ".my_vars")
float KDx = 40.0;
#pragma DATA_SECTION(KDy, ".my_vars")
float KDy = 250.0;
#pragma DATA_SECTION(KDz, ".my_vars")
float KDz = 250.0;
/* frame N: R = Rz(thz) Rx(thx) Ry(thy) */
#pragma DATA_SECTION(thz, ".my_vars")
float thz = 0.0;
#pragma DATA_SECTION(thx, ".my_vars")
float thx = 0.0;
#pragma DATA_SECTION(thy, ".my_vars")
float thy = 0.0;

float p4 = 0.0753;   /* the course's gravity parameters, command units */
float p5 = 0.0298;

long mycount = 0;
float x = 0, y = 0, z = 0;            /* end effector, m */
float xd = 0, yd = 0, zd = 0;         /* the point held, m */
float x_old = 0, y_old = 0, z_old = 0;
float xdot_old1[3] = {0, 0, 0}, xdot_old2[3] = {0, 0, 0};
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
    /* the Jacobian of x y z (m) with respect to the motor angles (rad) */
    float J11 = -L * s1 * (c3 + s2), J12 = L * c1 * c2, J13 = -L * c1 * s3;
    float J21 = L * c1 * (c3 + s2),  J22 = L * s1 * c2, J23 = -L * s1 * s3;
    float J31 = 0,                   J32 = -L * s2,     J33 = -L * c3;
    /* R = Rz(thz) Rx(thx) Ry(thy) */
    float cz = cos(thz), sz = sin(thz), cx = cos(thx), sx = sin(thx), cy = cos(thy), sy = sin(thy);
    float R11 = cz * cy - sz * sx * sy, R12 = -sz * cx, R13 = cz * sy + sz * sx * cy;
    float R21 = sz * cy + cz * sx * sy, R22 = cz * cx,  R23 = sz * sy - cz * sx * cy;
    float R31 = -cx * sy,               R32 = sx,       R33 = cx * cy;
    float e[3], v[3], eN[3], vN[3], FN[3], F[3], xdot[3];
    int j;

    x = L * c1 * (c3 + s2);
    y = L * s1 * (c3 + s2);
    z = L * (1 + c2 - s3);
    if (mycount == 0) {   /* hold the point where the arm is at the first call */
        xd = x;
        yd = y;
        zd = z;
        x_old = x;
        y_old = y;
        z_old = z;
    }
    xdot[0] = (x - x_old) / 0.001;
    xdot[1] = (y - y_old) / 0.001;
    xdot[2] = (z - z_old) / 0.001;
    for (j = 0; j < 3; j++) {
        xdot[j] = (xdot[j] + xdot_old1[j] + xdot_old2[j]) / 3.0;
        xdot_old2[j] = xdot_old1[j];
        xdot_old1[j] = xdot[j];
    }
    x_old = x;
    y_old = y;
    z_old = z;

    /* error and velocity in frame N (R^T times the world's), the law there, back to the world */
    e[0] = xd - x;
    e[1] = yd - y;
    e[2] = zd - z;
    v[0] = xdot[0];
    v[1] = xdot[1];
    v[2] = xdot[2];
    eN[0] = R11 * e[0] + R21 * e[1] + R31 * e[2];
    eN[1] = R12 * e[0] + R22 * e[1] + R32 * e[2];
    eN[2] = R13 * e[0] + R23 * e[1] + R33 * e[2];
    vN[0] = R11 * v[0] + R21 * v[1] + R31 * v[2];
    vN[1] = R12 * v[0] + R22 * v[1] + R32 * v[2];
    vN[2] = R13 * v[0] + R23 * v[1] + R33 * v[2];
    FN[0] = KPx * eN[0] - KDx * vN[0];
    FN[1] = KPy * eN[1] - KDy * vN[1];
    FN[2] = KPz * eN[2] - KDz * vN[2];
    F[0] = R11 * FN[0] + R12 * FN[1] + R13 * FN[2];
    F[1] = R21 * FN[0] + R22 * FN[1] + R23 * FN[2];
    F[2] = R31 * FN[0] + R32 * FN[1] + R33 * FN[2];

    *tau1 = (J11 * F[0] + J21 * F[1] + J31 * F[2]) / NM_PER_UNIT;
    *tau2 = (J12 * F[0] + J22 * F[1] + J32 * F[2]) / NM_PER_UNIT - p4 * GRAV * s2;
    *tau3 = (J13 * F[0] + J23 * F[1] + J33 * F[2]) / NM_PER_UNIT - p5 * GRAV * c3;

    if ((mycount % 500) == 0) {
        printxyz[0] = x / 0.0254;
        printxyz[1] = y / 0.0254;
        printxyz[2] = z / 0.0254;
        UARTprint = 1;
    }
    Simulink_PlotVar1 = x;
    Simulink_PlotVar2 = y;
    Simulink_PlotVar3 = z;
    Simulink_PlotVar4 = error;
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%.2f %.2f %.2f\n\r", printxyz[0], printxyz[1], printxyz[2]);
}
