/* A position press at a set speed and gain: the target goes 5 mm into the egg at 15 mm/s with a
 * stiff z axis (Kpress) and stays there 3 s, the Lab 3 friction compensation on as everywhere else
 * (the joints' speeds here, 0.04-0.06 rad/s, straddle its minimum velocity: the arm comes down in
 * lurches and touches the egg faster than its target; docs/worlds.md, "What presses do on it").
 * A Gen A ("CRSRobot") file.
 *
 * The final project in one run, on the bench position_press.toml (beside this file): the peg in the hole,
 * over the obstacle, along the zig-zag groove, the egg pressed. The path is a table of waypoints
 * (the lab's forward kinematics point, m); the desired point moves on a straight line to each at
 * its speed, then waits its hold; task-space impedance F = K (xd - x) + D (vd - v), tau = J^T F
 * plus the course's gravity and Lab 3 friction compensation (command units). */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

/* the bench, measured with the peg: the lab's forward kinematics at each fixture (m) */
#define HOLE_X 0.03
#define HOLE_Y 0.345
#define HOLE_TOP 0.170
#define POST_X 0.19
#define POST_Y 0.105
#define POST_TOP 0.300
#define G0X 0.375
#define G0Y 0.092
#define G1X 0.402
#define G1Y 0.037
#define G2X 0.312
#define G2Y 0.017
#define G3X 0.372
#define G3Y -0.088
#define EGG_X 0.205
#define EGG_Y 0.179
#define EGG_TOP 0.2975
#define INSERT 0.040   /* m below the hole's top */
#define GROOVE_Z 0.212
#define PRESS_DEPTH 0.005

/* the arm's resting motor angles (rad), found in Lab 1 on this bench */
float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;

/* segment modes */
#define STIFF 0   /* every axis stiff: moving in free air */
#define SOFTXY 1  /* x and y soft, z stiff: the hole's chamfer centres the peg */
#define GROOVE 2  /* soft across the segment, stiff along it and in z */
#define PRESS 3   /* the egg, pressed the way this file says above */

typedef struct {
    float x, y, z;   /* m: where the segment ends */
    float speed;     /* m/s along the straight line there */
    int mode;
    float hold;      /* s at the end */
} waypoint;

/* gains: command units per m, per m/s */
float Kstiff = 600.0, Dstiff = 20.0;
float Ksoft = 15.0, Dsoft = 2.5;
float Kacross = 50.0;
float fric_scale = 0.8;      /* of the Lab 3 friction compensation */
float tau_max = 3.5;         /* the motor board cuts out after 0.5 s beyond 4 */

float p4 = 0.0753, p5 = 0.0298;
float Vpos[3] = {0.2513, 0.2500, 0.1922};
float Vneg[3] = {0.2477, 0.2870, 0.2132};
float Cpos[3] = {0.3637, 0.4759, 0.5339};
float Cneg[3] = {-0.2948, -0.5031, -0.5190};
float vmin[3] = {0.1, 0.05, 0.05};

void press(float F[3], const float e[3], const float ev[3], const float v[3], float *fc);
float J[3][3];            /* d(x y z)/d(motor angles), m/rad: this tick's Jacobian */
float tau_ff[3] = {0, 0, 0};  /* a press's own torques, command units */

int seg = 0;
float seg_t = 0;
float start[3] = {0, 0, 0}, xd[3] = {0, 0, 0}, vd[3] = {0, 0, 0}, x[3] = {0, 0, 0};
float theta_old[3] = {0, 0, 0}, om1[3] = {0, 0, 0}, om2[3] = {0, 0, 0};
float press_t = 0;
int print_seg = 0;
float print_mm[3] = {0, 0, 0};

float Kpress = 800.0;   /* command units per m: the press's stiffness */

#define NPOINTS 16
waypoint path[NPOINTS] = {
    {0.150, 0.150, 0.420, 0.15, STIFF, 0.0},     /* out of the resting pose */
    {HOLE_X, HOLE_Y, HOLE_TOP + 0.030, 0.30, STIFF, 0.2},   /* above the hole */
    {HOLE_X, HOLE_Y, HOLE_TOP + 0.004, 0.05, STIFF, 0.2},   /* 4 mm over its top */
    {HOLE_X, HOLE_Y, HOLE_TOP - INSERT, 0.05, SOFTXY, 0.8}, /* in, soft in x and y, held */
    {HOLE_X, HOLE_Y, HOLE_TOP + 0.030, 0.10, SOFTXY, 0.0},  /* out */
    {HOLE_X, HOLE_Y, 0.380, 0.30, STIFF, 0.0},   /* up, clear of the post */
    {POST_X, POST_Y, 0.380, 0.30, STIFF, 0.0},   /* over the obstacle */
    {G0X, G0Y, GROOVE_Z + 0.050, 0.30, STIFF, 0.1},  /* above the entrance */
    {G0X, G0Y, GROOVE_Z, 0.05, STIFF, 0.1},          /* into the groove */
    {G1X, G1Y, GROOVE_Z, 0.08, GROOVE, 0.0},     /* first corner */
    {G2X, G2Y, GROOVE_Z, 0.08, GROOVE, 0.0},     /* second corner */
    {G3X, G3Y, GROOVE_Z, 0.08, GROOVE, 0.1},     /* the exit */
    {G3X, G3Y, 0.330, 0.20, STIFF, 0.0},         /* out of the groove */
    {EGG_X, EGG_Y, EGG_TOP + 0.030, 0.30, STIFF, 0.2},   /* above the egg */
    {EGG_X, EGG_Y, EGG_TOP - PRESS_DEPTH, 0.015, PRESS, 3.0}, /* the press, held */
    {EGG_X, EGG_Y, 0.350, 0.10, STIFF, 1000.0}  /* off the egg, and stay */
};

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

float friction(int j, float w)
{
    if (w > vmin[j]) return Vpos[j] * w + Cpos[j];
    if (w < -vmin[j]) return Vneg[j] * w + Cneg[j];
    return 3.6 * w;
}

float clamp(float u)
{
    return u > tau_max ? tau_max : (u < -tau_max ? -tau_max : u);
}

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    float c1 = cos(theta1motor), s1 = sin(theta1motor);
    float c2 = cos(theta2motor), s2 = sin(theta2motor);
    float c3 = cos(theta3motor), s3 = sin(theta3motor);
    float L = 0.254;
    float J11 = -L * s1 * (c3 + s2), J12 = L * c1 * c2, J13 = -L * c1 * s3;
    float J21 = L * c1 * (c3 + s2),  J22 = L * s1 * c2, J23 = -L * s1 * s3;
    float J31 = 0,                   J32 = -L * s2,     J33 = -L * c3;
    float th[3], w[3], v[3], e[3], ev[3], F[3], K[3], D[3], d[3];
    float len, T, s, a, ca, sa, e_al, e_ac, v_al, v_ac, F_al, F_ac, fc;
    waypoint *p;
    int j;

    x[0] = L * c1 * (c3 + s2);
    x[1] = L * s1 * (c3 + s2);
    x[2] = L * (1 + c2 - s3);
    th[0] = theta1motor;
    th[1] = theta2motor;
    th[2] = theta3motor;
    if (mycount == 0) {
        for (j = 0; j < 3; j++) {
            start[j] = x[j];
            theta_old[j] = th[j];
        }
    }
    for (j = 0; j < 3; j++) {
        w[j] = (th[j] - theta_old[j]) / 0.001;
        w[j] = (w[j] + om1[j] + om2[j]) / 3.0;
        theta_old[j] = th[j];
        om2[j] = om1[j];
        om1[j] = w[j];
    }
    J[0][0] = J11; J[0][1] = J12; J[0][2] = J13;
    J[1][0] = J21; J[1][1] = J22; J[1][2] = J23;
    J[2][0] = J31; J[2][1] = J32; J[2][2] = J33;
    v[0] = J11 * w[0] + J12 * w[1] + J13 * w[2];
    v[1] = J21 * w[0] + J22 * w[1] + J23 * w[2];
    v[2] = J31 * w[0] + J32 * w[1] + J33 * w[2];

    /* the desired point: a straight line at the segment's speed, then the hold */
    p = &path[seg];
    d[0] = p->x - start[0];
    d[1] = p->y - start[1];
    d[2] = p->z - start[2];
    len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    T = len / p->speed;
    s = (T > 0) ? seg_t / T : 1;
    for (j = 0; j < 3; j++) {
        xd[j] = (s < 1) ? start[j] + s * d[j] : start[j] + d[j];
        vd[j] = (s < 1) ? d[j] / T : 0;
    }
    seg_t += 0.001;
    if (s >= 1 && seg_t >= T + p->hold && seg < NPOINTS - 1) {
        for (j = 0; j < 3; j++) start[j] = x[j];   /* the next line starts where the arm is */
        seg++;
        seg_t = 0;
        press_t = 0;
    }

    for (j = 0; j < 3; j++) {
        e[j] = xd[j] - x[j];
        ev[j] = vd[j] - v[j];
        K[j] = Kstiff;
        D[j] = Dstiff;
    }
    fc = fric_scale;
    if (p->mode == SOFTXY) {
        K[0] = K[1] = Ksoft;
        D[0] = D[1] = Dsoft;
    }
    if (p->mode == GROOVE) {
        /* the stiffness frame turned along the segment: soft across it */
        a = atan2(d[1], d[0]);
        ca = cos(a);
        sa = sin(a);
        e_al = ca * e[0] + sa * e[1];
        e_ac = -sa * e[0] + ca * e[1];
        v_al = ca * ev[0] + sa * ev[1];
        v_ac = -sa * ev[0] + ca * ev[1];
        F_al = Kstiff * e_al + Dstiff * v_al;
        F_ac = Kacross * e_ac + Dsoft * v_ac;
        F[0] = ca * F_al - sa * F_ac;
        F[1] = sa * F_al + ca * F_ac;
        F[2] = Kstiff * e[2] + Dstiff * ev[2];
    } else {
        for (j = 0; j < 3; j++) F[j] = K[j] * e[j] + D[j] * ev[j];
    }
    tau_ff[0] = tau_ff[1] = tau_ff[2] = 0;
    if (p->mode == PRESS) {
        press(F, e, ev, v, &fc);
        press_t += 0.001;
    }

    *tau1 = J11 * F[0] + J21 * F[1] + J31 * F[2] + tau_ff[0] + fc * friction(0, w[0]);
    *tau2 = J12 * F[0] + J22 * F[1] + J32 * F[2] + tau_ff[1] + fc * friction(1, w[1]) - p4 * GRAV * sin(theta2motor);
    *tau3 = J13 * F[0] + J23 * F[1] + J33 * F[2] + tau_ff[2] + fc * friction(2, w[2]) - p5 * GRAV * cos(theta3motor);
    *tau1 = clamp(*tau1);
    *tau2 = clamp(*tau2);
    *tau3 = clamp(*tau3);

    if ((mycount % 500) == 0) {
        print_seg = seg;
        for (j = 0; j < 3; j++) print_mm[j] = 1000 * x[j];
        SWI_post(&SWI_printf);
    }
    Simulink_PlotVar1 = x[0];
    Simulink_PlotVar2 = x[1];
    Simulink_PlotVar3 = x[2];
    Simulink_PlotVar4 = seg;
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "seg %d  %.1f %.1f %.1f mm\n\r", print_seg, print_mm[0], print_mm[1], print_mm[2]);
}

void press(float F[3], const float e[3], const float ev[3], const float v[3], float *fc)
{
    (void)fc;   /* the friction compensation stays as it is */
    F[2] = Kpress * e[2] + Dstiff * ev[2];
}
