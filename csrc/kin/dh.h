/* Denavit-Hartenberg link transforms. Angles in radians, lengths in the caller's unit.
 * Matrices are row-major 4x4 (16 doubles), caller-owned. */
#ifndef CRSLAB_DH_H
#define CRSLAB_DH_H

/* Standard (distal) DH: Rot_z(theta) Trans_z(d) Trans_x(a) Rot_x(alpha). */
void dh_standard_transform(double a, double alpha_rad, double d, double theta_rad, double out[16]);

/* out = a * b for row-major 4x4 homogeneous transforms; out may alias neither a nor b. */
void mat4_mul(const double a[16], const double b[16], double out[16]);

#endif
