#include "crs_arm.h"

#include <math.h>

#include "dh.h"
#include "vector_math.h"

static const double HALF_PI = 1.57079632679489661923;

/* Rows per block in the batch loops: sines and cosines of a block are taken in their own
 * loops (so they vectorize), then combined. */
enum { BLOCK = 256 };

void crs_motor_to_dh(const double motor_rad[3], double dh_rad[3])
{
    const double m2 = motor_rad[1];
    dh_rad[0] = motor_rad[0];
    dh_rad[1] = m2 - HALF_PI;
    dh_rad[2] = motor_rad[2] - m2 + HALF_PI;
}

void crs_dh_to_motor(const double dh_rad[3], double motor_rad[3])
{
    const double d2 = dh_rad[1];
    motor_rad[0] = dh_rad[0];
    motor_rad[1] = d2 + HALF_PI;
    motor_rad[2] = dh_rad[2] + d2; /* motor 3 reads the forearm's absolute angle */
}

void crs_fk_pose_dh(const double dh_rad[3], double pose_in[16])
{
    double a1[16], a2[16], a3[16], t12[16];
    dh_standard_transform(0.0, -HALF_PI, CRS_BASE_HEIGHT_IN, dh_rad[0], a1);
    dh_standard_transform(CRS_UPPER_ARM_IN, 0.0, 0.0, dh_rad[1], a2);
    dh_standard_transform(CRS_FOREARM_IN, 0.0, 0.0, dh_rad[2], a3);
    mat4_mul(a1, a2, t12);
    mat4_mul(t12, a3, pose_in);
}

/* FK in motor angles from their sines and cosines: th2 DH = th2M - pi/2 and th2 + th3 DH = th3M,
 * so x = cos th1 (a2 sin th2M + a3 cos th3M), z = d1 + a2 cos th2M - a3 sin th3M. */
static inline void fk_motor_sincos(const double s[3], const double c[3], double xyz_in[3])
{
    const double reach = CRS_UPPER_ARM_IN * s[1] + CRS_FOREARM_IN * c[2];
    xyz_in[0] = c[0] * reach;
    xyz_in[1] = s[0] * reach;
    xyz_in[2] = CRS_BASE_HEIGHT_IN + CRS_UPPER_ARM_IN * c[1] - CRS_FOREARM_IN * s[2];
}

/* z of crs_fk_motor alone (the same expression), from two of its six sines and cosines */
static inline double fk_height_motor_in(const double motor_rad[3])
{
    return CRS_BASE_HEIGHT_IN + CRS_UPPER_ARM_IN * cos(motor_rad[1]) - CRS_FOREARM_IN * sin(motor_rad[2]);
}

void crs_fk_motor(const double motor_rad[3], double xyz_in[3])
{
    const double s[3] = {sin(motor_rad[0]), sin(motor_rad[1]), sin(motor_rad[2])};
    const double c[3] = {cos(motor_rad[0]), cos(motor_rad[1]), cos(motor_rad[2])};
    fk_motor_sincos(s, c, xyz_in);
}

void crs_fk_dh(const double dh_rad[3], double xyz_in[3])
{
    double motor[3];
    crs_dh_to_motor(dh_rad, motor);
    crs_fk_motor(motor, xyz_in);
}

/* The closed-form IK, branch-free so the batch loop vectorizes. In the (r, s) plane through the
 * arm, with psi1 = -th2 and psi2 = -th3 (positive th2 lowers the arm), it is the planar two-link
 * solution; c3 clamped to [-1, 1] gives the documented answers for unreachable targets. */
static inline int ik_dh_core(const double xyz_in[3], int elbow_up, double dh_rad[3])
{
    const double l2 = CRS_UPPER_ARM_IN, l3 = CRS_FOREARM_IN;
    const double x = xyz_in[0], y = xyz_in[1];
    const double r = sqrt(x * x + y * y);            /* horizontal reach, in */
    const double s = xyz_in[2] - CRS_BASE_HEIGHT_IN; /* height above the shoulder, in */
    const double dist2 = r * r + s * s;
    const double outer2 = (l2 + l3) * (l2 + l3), inner2 = (l2 - l3) * (l2 - l3);
    /* 1 - c3 and 1 + c3 without cancellation (c3 = cos th3 DH) */
    double one_minus = (outer2 - dist2) / (2.0 * l2 * l3);
    double one_plus = (dist2 - inner2) / (2.0 * l2 * l3);
    const int far = one_minus < 0.0, near = one_plus < 1e-18;
    one_minus = far ? 0.0 : (near ? 2.0 : one_minus);
    one_plus = far ? 2.0 : (near ? 0.0 : one_plus);
    const double c3 = one_plus - 1.0;
    const double s3 = (elbow_up ? 1.0 : -1.0) * sqrt(one_minus * one_plus);
    /* psi1 = atan2(s, r) - atan2(l3 sin psi2, l2 + l3 cos psi2), as one atan2 */
    const double k1 = l2 + l3 * c3, k2 = -l3 * s3;
    /* on the base axis (closer than 1e-9 in) any th1 works: 0 is the documented convention */
    dh_rad[0] = (r > 1e-9) ? atan2(y, x) : 0.0;
    dh_rad[1] = -atan2(s * k1 - r * k2, r * k1 + s * k2);
    dh_rad[2] = atan2(s3, c3);
    return far ? CRS_IK_UNREACHABLE
               : (near ? (inner2 < 1e-18 && dist2 < 1e-18 ? CRS_IK_SHOULDER : CRS_IK_UNREACHABLE)
                       : CRS_IK_OK);
}

crs_ik_status crs_ik_dh(const double xyz_in[3], int elbow_up, double dh_rad[3])
{
    return (crs_ik_status)ik_dh_core(xyz_in, elbow_up, dh_rad);
}

crs_ik_status crs_ik_motor(const double xyz_in[3], int elbow_up, double motor_rad[3])
{
    double dh[3];
    const crs_ik_status status = crs_ik_dh(xyz_in, elbow_up, dh);
    crs_dh_to_motor(dh, motor_rad);
    return status;
}

int crs_outside_envelope_motor(const double motor_rad[3])
{
    /* called every tick: the joint bounds first, then the height alone, only when they hold */
    double dh[3];
    crs_motor_to_dh(motor_rad, dh);
    return fabs(dh[0]) > CRS_ENVELOPE_TH1_MAX_RAD || dh[1] < CRS_ENVELOPE_TH2_MIN_RAD
        || dh[1] > CRS_ENVELOPE_TH2_MAX_RAD || dh[2] < CRS_ENVELOPE_TH3_MIN_RAD
        || dh[2] > CRS_ENVELOPE_TH3_MAX_RAD
        || fk_height_motor_in(motor_rad) < CRS_ENVELOPE_Z_MIN_IN;
}

void crs_outside_envelope_motor_batch(const double *motor_rad, int *outside, size_t n)
{
    for (size_t i = 0; i < n; ++i) outside[i] = crs_outside_envelope_motor(motor_rad + 3 * i);
}

void crs_jacobian_motor(const double motor_rad[3], double jac[9])
{
    const double c1 = cos(motor_rad[0]), s1 = sin(motor_rad[0]);
    const double c2 = cos(motor_rad[1]), s2 = sin(motor_rad[1]);
    const double c3 = cos(motor_rad[2]), s3 = sin(motor_rad[2]);
    const double reach = CRS_UPPER_ARM_IN * s2 + CRS_FOREARM_IN * c3;
    jac[0] = -s1 * reach; jac[1] = c1 * CRS_UPPER_ARM_IN * c2; jac[2] = -c1 * CRS_FOREARM_IN * s3;
    jac[3] = c1 * reach;  jac[4] = s1 * CRS_UPPER_ARM_IN * c2; jac[5] = -s1 * CRS_FOREARM_IN * s3;
    jac[6] = 0.0;         jac[7] = -CRS_UPPER_ARM_IN * s2;      jac[8] = -CRS_FOREARM_IN * c3;
}

void crs_motor_to_dh_batch(const double *motor_rad, double *dh_rad, size_t n)
{
    for (size_t i = 0; i < n; ++i) crs_motor_to_dh(motor_rad + 3 * i, dh_rad + 3 * i);
}

void crs_dh_to_motor_batch(const double *dh_rad, double *motor_rad, size_t n)
{
    for (size_t i = 0; i < n; ++i) crs_dh_to_motor(dh_rad + 3 * i, motor_rad + 3 * i);
}

CRS_VECTOR_CLONES
static void sin_cos_block(const double *restrict a, double *restrict sa, double *restrict ca,
                          size_t m)
{
    for (size_t i = 0; i < m; ++i) sa[i] = sin(a[i]);
    for (size_t i = 0; i < m; ++i) ca[i] = cos(a[i]);
}

void crs_fk_motor_batch(const double *motor_rad, double *xyz_in, size_t n)
{
    double s[3 * BLOCK], c[3 * BLOCK];
    for (size_t b = 0; b < n; b += BLOCK) {
        const size_t m = (n - b < BLOCK) ? n - b : BLOCK;
        sin_cos_block(motor_rad + 3 * b, s, c, 3 * m);
        for (size_t i = 0; i < m; ++i) fk_motor_sincos(s + 3 * i, c + 3 * i, xyz_in + 3 * (b + i));
    }
}

void crs_fk_dh_batch(const double *dh_rad, double *xyz_in, size_t n)
{
    double motor[3 * BLOCK];
    for (size_t b = 0; b < n; b += BLOCK) {
        const size_t m = (n - b < BLOCK) ? n - b : BLOCK;
        crs_dh_to_motor_batch(dh_rad + 3 * b, motor, m);
        crs_fk_motor_batch(motor, xyz_in + 3 * b, m);
    }
}

/* The arrays never overlap (restrict; crs_arm.h): without it gcc checks at run time whether they
 * do and takes a scalar loop when they lie close together in memory, whose libm atan2 differs in
 * its last bits from the vector one: the same points would get other angles by where they lie. */
CRS_VECTOR_CLONES
void crs_ik_dh_batch(const double *restrict xyz_in, int elbow_up, double *restrict dh_rad, int *restrict status,
                     size_t n)
{
    for (size_t i = 0; i < n; ++i) status[i] = ik_dh_core(xyz_in + 3 * i, elbow_up, dh_rad + 3 * i);
}

void crs_ik_motor_batch(const double *restrict xyz_in, int elbow_up, double *restrict motor_rad,
                        int *restrict status, size_t n)
{
    crs_ik_dh_batch(xyz_in, elbow_up, motor_rad, status, n);
    for (size_t i = 0; i < n; ++i) {
        double *q = motor_rad + 3 * i;
        const double dh[3] = {q[0], q[1], q[2]};
        crs_dh_to_motor(dh, q);
    }
}

void crs_jacobian_motor_batch(const double *motor_rad, double *jac, size_t n)
{
    for (size_t i = 0; i < n; ++i) crs_jacobian_motor(motor_rad + 3 * i, jac + 9 * i);
}
