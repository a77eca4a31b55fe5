#include "closed_ik.h"

#include <math.h>

#include "vector_math.h" /* atan2 declared as libmvec has it in every file that calls it (see there) */

static const double PI = 3.14159265358979323846;
/* Relative slack on the reach boundary: a target this close outside still counts as reached. */
static const double REACH_SLACK = 1e-12;
/* An angle this close outside a limit (rad) is rounding, and is moved onto the limit. */
static const double LIMIT_SLACK_RAD = 1e-9;

/* Angle into (-pi, pi]. */
static double wrap(double a)
{
    double w = remainder(a, 2.0 * PI);
    return w <= -PI ? w + 2.0 * PI : w;
}

/* Planar two-link IK for the point (u, w) with links l1, l2; elbow_sign picks the sign of the
 * second angle. Returns 1 if reachable; otherwise writes the stretched or folded pose toward it. */
static int two_link(double u, double w, double l1, double l2, double elbow_sign, double *q1, double *q2)
{
    const double dist2 = u * u + w * w;
    const double outer2 = (l1 + l2) * (l1 + l2), inner2 = (l1 - l2) * (l1 - l2);
    /* 1 - cos q2 and 1 + cos q2, each computed without cancellation */
    double one_minus = (outer2 - dist2) / (2.0 * l1 * l2);
    double one_plus = (dist2 - inner2) / (2.0 * l1 * l2);
    const int reachable = one_minus >= -REACH_SLACK && one_plus >= -REACH_SLACK;
    /* the two add up to 2; clamping both keeps that for targets out of reach */
    one_minus = fmin(fmax(one_minus, 0.0), 2.0);
    one_plus = fmin(fmax(one_plus, 0.0), 2.0);
    const double c2 = one_plus - 1.0, s2 = elbow_sign * sqrt(one_minus * one_plus);
    const double k1 = l1 + l2 * c2, k2 = l2 * s2;
    *q1 = atan2(w * k1 - u * k2, u * k1 + w * k2); /* atan2(w, u) - atan2(k2, k1) */
    *q2 = atan2(s2, c2);
    return reachable;
}

/* Shift each angle by 2 pi if that brings it inside its limits; 1 if all end up inside. */
static int fit_limits(const double *lower, const double *upper, double *q)
{
    int inside = 1;
    for (int j = 0; j < 3; ++j) {
        const double lo = lower ? lower[j] : -INFINITY, hi = upper ? upper[j] : INFINITY;
        if (q[j] < lo && q[j] >= lo - LIMIT_SLACK_RAD) q[j] = lo;
        if (q[j] > hi && q[j] <= hi + LIMIT_SLACK_RAD) q[j] = hi;
        if (q[j] >= lo && q[j] <= hi) continue;
        if (q[j] - 2.0 * PI >= lo && q[j] - 2.0 * PI <= hi) {
            q[j] -= 2.0 * PI;
        } else if (q[j] + 2.0 * PI >= lo && q[j] + 2.0 * PI <= hi) {
            q[j] += 2.0 * PI;
        } else {
            inside = 0;
        }
    }
    return inside;
}

int rrr_ik(const double dims[4], const double *lower, const double *upper, const double xyz[3], double q[12],
           int status[4])
{
    const double d1 = dims[0], a1 = dims[1], a2 = dims[2], a3 = dims[3];
    const double rho = hypot(xyz[0], xyz[1]), w = xyz[2] - d1;
    const double scale = a1 + a2 + a3 + fabs(d1);
    int flags = IK_SINGULAR_NONE;
    if (rho <= 1e-12 * scale) flags |= IK_SINGULAR_BASE;
    const double heading = atan2(xyz[1], xyz[0]); /* 0 on the base axis */
    for (int slot = 0; slot < RRR_IK_SLOTS; ++slot) {
        const int back = slot >= 2;
        const double u = back ? -rho - a1 : rho - a1; /* reach beyond link 1 along its own x axis */
        if (u * u + w * w <= 1e-24 * scale * scale && fabs(a2 - a3) <= 1e-12 * scale) {
            flags |= IK_SINGULAR_CENTRE;
        }
        double *s = q + 3 * slot;
        s[0] = wrap(back ? heading + PI : heading);
        const int reachable = two_link(u, w, a2, a3, (slot % 2 == 0) ? 1.0 : -1.0, &s[1], &s[2]);
        s[1] = wrap(s[1]);
        s[2] = wrap(s[2]);
        status[slot] = !reachable ? IK_SLOT_UNREACHABLE
                                  : (fit_limits(lower, upper, s) ? IK_SLOT_OK : IK_SLOT_OUT_OF_LIMITS);
    }
    return flags;
}

int planar3r_ik(const double links[3], const double *lower, const double *upper, const double target[3],
                double q[6], int status[2])
{
    const double a1 = links[0], a2 = links[1], a3 = links[2], phi = target[2];
    const double xc = target[0] - a3 * cos(phi), yc = target[1] - a3 * sin(phi); /* wrist point */
    const double scale = a1 + a2 + a3;
    int flags = IK_SINGULAR_NONE;
    if (xc * xc + yc * yc <= 1e-24 * scale * scale && fabs(a1 - a2) <= 1e-12 * scale) {
        flags |= IK_SINGULAR_CENTRE;
    }
    for (int slot = 0; slot < PLANAR3R_IK_SLOTS; ++slot) {
        double *s = q + 3 * slot;
        const int reachable = two_link(xc, yc, a1, a2, slot == 0 ? 1.0 : -1.0, &s[0], &s[1]);
        s[0] = wrap(s[0]);
        s[1] = wrap(s[1]);
        s[2] = wrap(phi - s[0] - s[1]);
        status[slot] = !reachable ? IK_SLOT_UNREACHABLE
                                  : (fit_limits(lower, upper, s) ? IK_SLOT_OK : IK_SLOT_OUT_OF_LIMITS);
    }
    return flags;
}

void rrr_ik_batch(const double dims[4], const double *lower, const double *upper, const double *xyz, double *q,
                  int *status, int *singular, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        singular[i] = rrr_ik(dims, lower, upper, xyz + 3 * i, q + 3 * RRR_IK_SLOTS * i, status + RRR_IK_SLOTS * i);
    }
}

void planar3r_ik_batch(const double links[3], const double *lower, const double *upper, const double *target,
                       double *q, int *status, int *singular, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        singular[i] = planar3r_ik(links, lower, upper, target + 3 * i, q + 3 * PLANAR3R_IK_SLOTS * i,
                                  status + PLANAR3R_IK_SLOTS * i);
    }
}
