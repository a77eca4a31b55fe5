/* Closed-form IK of the course's small arms, every solution at once, joint limits applied.
 * Angles in radians, lengths in the robot's unit. Returned angles lie in (-pi, pi] unless the
 * limits only admit the same angle shifted by 2 pi. An unusable solution slot still holds
 * finite angles (for an unreachable target, the arm stretched or folded toward it), never NaN.
 *
 * Spatial RRR (seed 003), standard DH (a, alpha, d, theta) =
 *   (a1, pi/2, d1, q1), (a2, 0, 0, q2), (a3, 0, 0, q3):
 *   x = (a1 + u) cos q1, y = (a1 + u) sin q1, z = d1 + w,
 *   u = a2 cos q2 + a3 cos(q2 + q3), w = a2 sin q2 + a3 sin(q2 + q3).
 * Four slots: [front, q3 >= 0], [front, q3 <= 0], [back, q3 >= 0], [back, q3 <= 0], where
 * front has q1 = atan2(y, x) and back q1 = atan2(y, x) + pi (the arm reaching over the base axis).
 *
 * Planar 3R (seeds 001 and 002), standard DH (a1, 0, 0, q1), (a2, 0, 0, q2), (a3, 0, 0, q3),
 * target (x, y, phi) with phi = q1 + q2 + q3: two slots, [q2 >= 0], [q2 <= 0].
 */
#ifndef CRSLAB_CLOSED_IK_H
#define CRSLAB_CLOSED_IK_H

#include <stddef.h>

enum { RRR_IK_SLOTS = 4, PLANAR3R_IK_SLOTS = 2 };

typedef enum {
    IK_SLOT_OK = 0,             /* an exact solution inside the limits */
    IK_SLOT_OUT_OF_LIMITS = 1,  /* an exact solution, but a joint is outside its limits */
    IK_SLOT_UNREACHABLE = 2     /* no exact solution on this branch */
} ik_slot_status;

/* Singular cases, as bit flags returned per target. */
typedef enum {
    IK_SINGULAR_NONE = 0,
    IK_SINGULAR_BASE = 1,    /* RRR target on the base axis (x = y = 0): any q1 works; q1 = 0 (front), pi (back) */
    IK_SINGULAR_CENTRE = 2   /* the wrist (planar 3R) or target (RRR) on the first moving link's axis
                                with equal link lengths: q1 (planar) or q2 (RRR) is free and set to 0 */
} ik_singular_flag;

/* dims = (d1, a1, a2, a3); lower, upper (3 each, rad) or NULL; q is 4 x 3, status 4.
 * Returns the ik_singular_flag bits of the target. */
int rrr_ik(const double dims[4], const double *lower, const double *upper, const double xyz[3], double q[12],
           int status[4]);

/* links = (a1, a2, a3); target = (x, y, phi_rad); q is 2 x 3, status 2. */
int planar3r_ik(const double links[3], const double *lower, const double *upper, const double target[3],
                double q[6], int status[2]);

/* Batch forms: n targets; q, status and singular hold n rows. */
void rrr_ik_batch(const double dims[4], const double *lower, const double *upper, const double *xyz, double *q,
                  int *status, int *singular, size_t n);
void planar3r_ik_batch(const double links[3], const double *lower, const double *upper, const double *target,
                       double *q, int *status, int *singular, size_t n);

#endif
