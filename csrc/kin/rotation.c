#include "rotation.h"

#include <math.h>

#include "vector_math.h" /* atan2 declared as libmvec has it in every file that calls it (see there) */

/* |v|, and v / |v| in unit (when |v| > 0), scaled first so that neither the squares nor the
 * quotient underflow or overflow (tiny angles give tiny, even subnormal, skew parts). */
static double normalize3(const double v[3], double unit[3])
{
    const double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    unit[0] = 0.0;
    unit[1] = 0.0;
    unit[2] = 0.0;
    if (!(m > 0.0) || !isfinite(m)) return m;
    const double x = v[0] / m, y = v[1] / m, z = v[2] / m;
    const double len = sqrt(x * x + y * y + z * z);
    unit[0] = x / len;
    unit[1] = y / len;
    unit[2] = z / len;
    return m * len;
}

rot_status rot_check(const double r[9], double tol, double *deviation)
{
    double worst = 0.0;
    for (int i = 0; i < 9; ++i) {
        if (!isfinite(r[i])) {
            if (deviation) *deviation = INFINITY;
            return ROT_NOT_FINITE;
        }
    }
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const double dot = r[3 * i] * r[3 * j] + r[3 * i + 1] * r[3 * j + 1] + r[3 * i + 2] * r[3 * j + 2];
            const double err = fabs(dot - (i == j));
            worst = err > worst ? err : worst;
        }
    }
    if (deviation) *deviation = worst;
    if (!(worst <= tol)) return ROT_NOT_ORTHONORMAL;
    const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6])
                       + r[2] * (r[3] * r[7] - r[4] * r[6]);
    return det < 0.0 ? ROT_REFLECTION : ROT_OK;
}

void rot_euler_zyx_to_matrix(const double zyx_rad[3], double r[9])
{
    const double ca = cos(zyx_rad[0]), sa = sin(zyx_rad[0]);
    const double cb = cos(zyx_rad[1]), sb = sin(zyx_rad[1]);
    const double cg = cos(zyx_rad[2]), sg = sin(zyx_rad[2]);
    r[0] = ca * cb; r[1] = ca * sb * sg - sa * cg; r[2] = ca * sb * cg + sa * sg;
    r[3] = sa * cb; r[4] = sa * sb * sg + ca * cg; r[5] = sa * sb * cg - ca * sg;
    r[6] = -sb;     r[7] = cb * sg;                r[8] = cb * cg;
}

int rot_matrix_to_euler_zyx(const double r[9], double zyx_rad[3])
{
    const double cb = hypot(r[0], r[3]);
    const int singular = cb < ROT_EULER_SINGULAR_COS;
    const double alpha = singular ? 0.0 : atan2(r[3], r[0]);
    const double ca = cos(alpha), sa = sin(alpha);
    zyx_rad[0] = alpha;
    zyx_rad[1] = atan2(-r[6], cb);
    /* gamma from Rot_z(-alpha) R = Rot_y(beta) Rot_x(gamma), whose middle row is (0, cg, -sg):
     * consistent with alpha even where alpha itself is ill-conditioned, and the singular case's
     * gamma = atan2(-r23, r22) when alpha = 0. */
    zyx_rad[2] = atan2(sa * r[2] - ca * r[5], ca * r[4] - sa * r[1]);
    return singular;
}

rot_status rot_axis_angle_to_matrix(const double axis[3], double angle_rad, double r[9])
{
    double n[3];
    const double len = normalize3(axis, n);
    if (!(len > 0.0) || !isfinite(len) || !isfinite(angle_rad)) {
        for (int i = 0; i < 9; ++i) r[i] = (i % 4 == 0);
        return ROT_ZERO_AXIS;
    }
    const double x = n[0], y = n[1], z = n[2];
    const double c = cos(angle_rad), s = sin(angle_rad), v = 1.0 - c;
    r[0] = c + x * x * v;     r[1] = x * y * v - z * s; r[2] = x * z * v + y * s;
    r[3] = y * x * v + z * s; r[4] = c + y * y * v;     r[5] = y * z * v - x * s;
    r[6] = z * x * v - y * s; r[7] = z * y * v + x * s; r[8] = c + z * z * v;
    return ROT_OK;
}

void rot_matrix_to_axis_angle(const double r[9], double axis[3], double *angle_rad)
{
    /* v = 2 sin(theta) n from the skew part, cos(theta) from the trace */
    const double v[3] = {r[7] - r[5], r[2] - r[6], r[3] - r[1]};
    double unit[3];
    const double two_sin = normalize3(v, unit);
    double c = 0.5 * (r[0] + r[4] + r[8] - 1.0);
    c = c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c);
    *angle_rad = atan2(0.5 * two_sin, c);
    if (c > -0.5) { /* theta < 120 deg: the skew part is well conditioned */
        if (two_sin > 0.0) {
            for (int i = 0; i < 3; ++i) axis[i] = unit[i];
        } else {
            axis[0] = 0.0; axis[1] = 0.0; axis[2] = 1.0;
        }
        return;
    }
    /* theta >= 120 deg: (R + R^T)/2 - cos(theta) I = (1 - cos(theta)) n n^T; read n from the
     * column with the largest diagonal, then take the sign that matches sin(theta) >= 0. */
    const double b[9] = {r[0] - c, 0.5 * (r[1] + r[3]), 0.5 * (r[2] + r[6]),
                         0.5 * (r[1] + r[3]), r[4] - c, 0.5 * (r[5] + r[7]),
                         0.5 * (r[2] + r[6]), 0.5 * (r[5] + r[7]), r[8] - c};
    int k = 0;
    if (b[4] > b[0]) k = 1;
    if (b[8] > b[4 * k]) k = 2;
    double n[3] = {b[k], b[3 + k], b[6 + k]};
    const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double sign = (n[0] * v[0] + n[1] * v[1] + n[2] * v[2]) < 0.0 ? -1.0 : 1.0;
    for (int i = 0; i < 3; ++i) axis[i] = sign * n[i] / len;
}

void rot_check_batch(const double *r, double tol, int *status, double *deviation, size_t n)
{
    for (size_t i = 0; i < n; ++i) status[i] = rot_check(r + 9 * i, tol, deviation ? deviation + i : NULL);
}

void rot_euler_zyx_to_matrix_batch(const double *zyx_rad, double *r, size_t n)
{
    for (size_t i = 0; i < n; ++i) rot_euler_zyx_to_matrix(zyx_rad + 3 * i, r + 9 * i);
}

void rot_matrix_to_euler_zyx_batch(const double *r, double *zyx_rad, int *singular, size_t n)
{
    for (size_t i = 0; i < n; ++i) singular[i] = rot_matrix_to_euler_zyx(r + 9 * i, zyx_rad + 3 * i);
}

void rot_axis_angle_to_matrix_batch(const double *axis, const double *angle_rad, double *r, int *status,
                                    size_t n)
{
    for (size_t i = 0; i < n; ++i) status[i] = rot_axis_angle_to_matrix(axis + 3 * i, angle_rad[i], r + 9 * i);
}

void rot_matrix_to_axis_angle_batch(const double *r, double *axis, double *angle_rad, size_t n)
{
    for (size_t i = 0; i < n; ++i) rot_matrix_to_axis_angle(r + 9 * i, axis + 3 * i, angle_rad + i);
}
