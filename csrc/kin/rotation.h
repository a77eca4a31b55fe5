/* Rotations: Euler ZYX angles, axis-angle and rotation matrices, both ways, with a check that a
 * matrix is a rotation. Matrices are row-major 3x3 (9 doubles), angles in radians.
 *
 * Euler ZYX (alpha, beta, gamma): R = Rot_z(alpha) Rot_y(beta) Rot_x(gamma), turning about z,
 * then the new y, then the newest x (yaw, pitch, roll). beta lies in [-pi/2, pi/2].
 * Axis-angle (n, theta): R = I + sin(theta) [n]x + (1 - cos(theta)) [n]x^2, |n| = 1, theta in [0, pi].
 * Pure functions on caller-owned memory.
 */
#ifndef CRSLAB_ROTATION_H
#define CRSLAB_ROTATION_H

#include <stddef.h>

/* cos(beta) below this is gimbal lock: alpha and gamma turn about the same axis. */
static const double ROT_EULER_SINGULAR_COS = 1e-12;
/* Default tolerance of rot_check on the entries of R R^T - I. */
static const double ROT_CHECK_TOL = 1e-6;

typedef enum {
    ROT_OK = 0,
    ROT_NOT_FINITE = 1,      /* an entry is NaN or infinite */
    ROT_NOT_ORTHONORMAL = 2, /* R R^T differs from I by more than the tolerance */
    ROT_REFLECTION = 3,      /* orthonormal, but det R = -1 */
    ROT_ZERO_AXIS = 4        /* axis-angle with a zero-length (or non-finite) axis */
} rot_status;

/* ROT_OK if R is a rotation within tol; *deviation (if not NULL) gets max |R R^T - I|. */
rot_status rot_check(const double r[9], double tol, double *deviation);

void rot_euler_zyx_to_matrix(const double zyx_rad[3], double r[9]);

/* Euler ZYX angles of R; returns 1 in the singular case cos(beta) < ROT_EULER_SINGULAR_COS,
 * where alpha = 0 by convention and gamma carries the whole turn about the shared axis
 * (beta = +-pi/2), else 0. Either way rot_euler_zyx_to_matrix gives R back. */
int rot_matrix_to_euler_zyx(const double r[9], double zyx_rad[3]);

/* R from a unit-or-not axis (normalised here) and an angle; ROT_ZERO_AXIS (and R = I) when the
 * axis has no direction. */
rot_status rot_axis_angle_to_matrix(const double axis[3], double angle_rad, double r[9]);

/* Unit axis and angle in [0, pi] of R. Angle 0 gives the axis (0, 0, 1); near pi the axis comes
 * from the symmetric part of R, so it stays accurate (its sign is then arbitrary at exactly pi). */
void rot_matrix_to_axis_angle(const double r[9], double axis[3], double *angle_rad);

/* Batch forms over n rows. */
void rot_check_batch(const double *r, double tol, int *status, double *deviation, size_t n);
void rot_euler_zyx_to_matrix_batch(const double *zyx_rad, double *r, size_t n);
void rot_matrix_to_euler_zyx_batch(const double *r, double *zyx_rad, int *singular, size_t n);
void rot_axis_angle_to_matrix_batch(const double *axis, const double *angle_rad, double *r, int *status,
                                    size_t n);
void rot_matrix_to_axis_angle_batch(const double *r, double *axis, double *angle_rad, size_t n);

#endif
