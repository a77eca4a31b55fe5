/* The CRS arm (CataLyst/A255, 3 driven joints): dimensions, motor<->DH angles, FK, IK, Jacobian.
 *
 * Units: lengths in inches (the course's unit), angles in radians.
 * "Motor angles" are what the lab's encoders report (docs/framework.md section 10); "DH angles" follow the
 * DH table (a, alpha, d, theta) = (0, -90 deg, 10, th1), (10, 0, 0, th2), (10, 0, 0, th3).
 * Pure functions on caller-owned memory; no globals.
 */
#ifndef CRSLAB_CRS_ARM_H
#define CRSLAB_CRS_ARM_H

#include <stddef.h>

/* The one definition of the arm's dimensions: every other part of crslab reads these. */
static const double CRS_BASE_HEIGHT_IN = 10.0; /* d1: floor of the DH frame 0 to the shoulder axis */
static const double CRS_UPPER_ARM_IN = 10.0;   /* a2: shoulder axis to elbow axis */
static const double CRS_FOREARM_IN = 10.0;     /* a3: elbow axis to the end-effector point */
static const double CRS_M_PER_IN = 0.0254;     /* exact */

/* The course framework's safety envelope (docs/framework.md section 3), on DH angles from the motor
 * angles and the end-effector height: outside it the framework holds the arm itself. */
static const double CRS_ENVELOPE_TH1_MAX_RAD = 0.6667 * 3.14159265358979323846; /* 0.6667 pi */
static const double CRS_ENVELOPE_TH2_MIN_RAD = -2.3;
static const double CRS_ENVELOPE_TH2_MAX_RAD = 0.15;
static const double CRS_ENVELOPE_TH3_MIN_RAD = 0.15;
static const double CRS_ENVELOPE_TH3_MAX_RAD = 2.3;
static const double CRS_ENVELOPE_Z_MIN_IN = 4.0;

/* IK status, one per target. */
typedef enum {
    CRS_IK_OK = 0,          /* exact solution */
    CRS_IK_UNREACHABLE = 1, /* farther than a2 + a3 from the shoulder: the returned angles point
                               the stretched arm at the target (the nearest reachable point) */
    CRS_IK_SHOULDER = 2     /* target on the shoulder axis centre (closer than a2 - a3 + 1e-9 in):
                               every th2 works; th2 = 0 DH, th3 = +-pi (folded) is returned */
} crs_ik_status;

void crs_motor_to_dh(const double motor_rad[3], double dh_rad[3]);
void crs_dh_to_motor(const double dh_rad[3], double motor_rad[3]);

/* Pose of DH frame 3 (the end effector) in frame 0, row-major 4x4, translation in inches. */
void crs_fk_pose_dh(const double dh_rad[3], double pose_in[16]);

/* End-effector position (inches) from DH angles or from motor angles (rad). */
void crs_fk_dh(const double dh_rad[3], double xyz_in[3]);
void crs_fk_motor(const double motor_rad[3], double xyz_in[3]);

/* Closed-form IK. elbow_up != 0 picks th3 DH >= 0 (the lab's choice), else th3 DH <= 0.
 * On the base axis (x, y within 1e-9 in of 0) th1 = 0 is returned (any th1 is a solution).
 * Never writes NaN: see crs_ik_status for what unreachable targets return. */
crs_ik_status crs_ik_dh(const double xyz_in[3], int elbow_up, double dh_rad[3]);
crs_ik_status crs_ik_motor(const double xyz_in[3], int elbow_up, double motor_rad[3]);

/* 1 when motor angles (rad) lie outside the framework's safety envelope, else 0. */
int crs_outside_envelope_motor(const double motor_rad[3]);
void crs_outside_envelope_motor_batch(const double *motor_rad, int *outside, size_t n);

/* d(xyz_in)/d(motor_rad), row-major 3x3, inches per radian. */
void crs_jacobian_motor(const double motor_rad[3], double jac_in_per_rad[9]);

/* Batch forms over n rows of 3 (row-major), for the numpy API; an output never overlaps an input. */
void crs_motor_to_dh_batch(const double *motor_rad, double *dh_rad, size_t n);
void crs_dh_to_motor_batch(const double *dh_rad, double *motor_rad, size_t n);
void crs_fk_motor_batch(const double *motor_rad, double *xyz_in, size_t n);
void crs_fk_dh_batch(const double *dh_rad, double *xyz_in, size_t n);
void crs_ik_motor_batch(const double *xyz_in, int elbow_up, double *motor_rad, int *status, size_t n);
void crs_ik_dh_batch(const double *xyz_in, int elbow_up, double *dh_rad, int *status, size_t n);
void crs_jacobian_motor_batch(const double *motor_rad, double *jac_in_per_rad, size_t n);

#endif
