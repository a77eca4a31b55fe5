/* Point-to-point joint trajectory profiles: Li's sinusoidal jerk, quintic (minimum jerk), cubic
 * and trapezoidal velocity; several joints synchronized to the slowest; piecewise paths.
 *
 * A profile is a small struct the caller owns: plan it once (traj_plan), then evaluate it at any
 * time t (traj_eval). Before t = 0 it rests at q0, after t = T at qf; between, position, velocity,
 * acceleration and jerk follow the profile's closed form. Pure functions, no globals, no
 * allocation: a lab file may include this header and link traj_profiles.c, e.g.
 *
 *     static traj_profile move;                        (plan once, say at the first lab() call)
 *     traj_plan(&move, TRAJ_LI, 0.0, 0.5236, 2.0, 0.0, 0.0);
 *     traj_sample d = traj_eval(&move, t_s);           (every tick: d.q_rad, d.qd_rad_s, ...)
 *
 * Units: time in seconds; positions in the joint's unit, radians for the course's revolute joints
 * (hence the _rad names), velocities per second, and so on. A speed or acceleration limit <= 0 or
 * infinite means "no limit".
 *
 * The profiles, for a move of L = qf - q0 in T seconds (peaks are magnitudes):
 *   TRAJ_LI         sinusoidal jerk (Huaizhong Li): an acceleration phase of Ta seconds whose
 *                   acceleration is (A/2)(1 - cos(2 pi t/Ta)), an optional cruise at V = A Ta/2,
 *                   and the mirror-image deceleration phase. Without a binding speed limit
 *                   Ta = T/2, A = 8L/T^2 (so Ta = sqrt(2L/A)), peak velocity 2L/T; when 2L/T
 *                   exceeds the speed limit, V is the limit and Ta = T - L/V. Position, velocity,
 *                   acceleration and jerk are continuous and the jerk is zero at both ends.
 *   TRAJ_QUINTIC    L(10s^3 - 15s^4 + 6s^5), s = t/T (minimum jerk): zero velocity and
 *                   acceleration at both ends; peak velocity 15L/(8T), acceleration 10L/(sqrt3 T^2).
 *   TRAJ_CUBIC      L(3s^2 - 2s^3): zero velocity at both ends; acceleration jumps to 6L/T^2 at
 *                   t = 0 and from -6L/T^2 at t = T; constant jerk -12L/T^3; peak velocity 1.5L/T.
 *   TRAJ_TRAPEZOID  constant acceleration for Ta, cruise at V, constant deceleration for Ta.
 *                   V = 1.5L/T (Ta = T/3) unless the speed limit is lower, then V is the limit and
 *                   Ta = T - L/V. The jerk is an impulse at each phase change and 0 elsewhere
 *                   (reported as 0 throughout); where the acceleration jumps inside (0, T) the
 *                   cruise value 0 is reported, at t = 0 and t = T the ramps' values.
 * traj_eval uses the closed forms on the closed interval [0, T], so the cubic's and the
 * trapezoid's accelerations at t = 0 and t = T are their ramps' values, not the rest's 0.
 */
#ifndef CRSLAB_TRAJ_PROFILES_H
#define CRSLAB_TRAJ_PROFILES_H

#include <stddef.h>

typedef enum {
    TRAJ_LI = 0,
    TRAJ_QUINTIC = 1,
    TRAJ_CUBIC = 2,
    TRAJ_TRAPEZOID = 3
} traj_kind;

typedef enum {
    TRAJ_OK = 0,
    TRAJ_BAD_ARGUMENT = 1, /* unknown kind, or a position, duration or limit that is NaN, or an
                              infinite position, or a negative or infinite duration */
    TRAJ_TOO_FAST = 2      /* the move cannot be made in that duration within the limits
                              (a zero duration with q0 != qf included) */
} traj_status;

/* One joint's planned move. Written by traj_plan; read-only afterwards. */
typedef struct {
    int kind;               /* traj_kind */
    double q0_rad;          /* start position: at rest there for t < 0 */
    double qf_rad;          /* final position: at rest there for t > duration_s */
    double distance_rad;    /* L = qf - q0, signed */
    double duration_s;      /* T >= 0 */
    double ramp_s;          /* Li, trapezoid: length Ta of the acceleration phase (and of the
                               deceleration phase); the cruise lasts T - 2 Ta. Others: T */
    double peak_vel_rad_s;  /* signed peak velocity (the cruise velocity for Li and trapezoid) */
    double peak_acc_rad_s2; /* signed peak acceleration (trapezoid: the ramp's constant value;
                               cubic: the value at t = 0) */
} traj_profile;

/* Position and its first three time derivatives at one instant. */
typedef struct {
    double q_rad;
    double qd_rad_s;
    double qdd_rad_s2;
    double qddd_rad_s3; /* jerk */
} traj_sample;

/* Plan one joint's move from q0 to qf taking exactly duration_s seconds. vmax_rad_s caps the
 * cruise velocity of Li and trapezoid profiles; any profile whose peak velocity or acceleration
 * would exceed a limit (by more than 1e-9 relative) gives TRAJ_TOO_FAST. q0 == qf is a rest of
 * that duration (zero duration allowed). On any failure *p is a rest at q0 (at 0 if q0 is not
 * finite), so evaluating it never produces NaN. */
traj_status traj_plan(traj_profile *p, traj_kind kind, double q0_rad, double qf_rad, double duration_s,
                      double vmax_rad_s, double amax_rad_s2);

/* The shortest duration for which traj_plan succeeds under these limits: with both limits, the
 * Li and trapezoid profiles cruise at vmax when the move is long enough. With only a speed limit
 * there is no shortest one for them (any T > L/vmax works, cruising, but the acceleration grows
 * without bound as T approaches L/vmax), so this returns the duration at which their unlimited
 * shape just reaches vmax (2L/vmax for Li, 1.5L/vmax for the trapezoid). No limit at all gives 0. */
traj_status traj_min_duration(traj_kind kind, double q0_rad, double qf_rad, double vmax_rad_s,
                              double amax_rad_s2, double *duration_s);

/* Plan n_joints moves of one kind that start together and end together, no joint exceeding its
 * limits: in duration_s if every joint can make its move in that time, else in the slowest
 * joint's traj_min_duration (so duration_s = 0 means "as fast as the limits allow"). Whether the
 * move was stretched shows in profiles[0].duration_s. vmax_rad_s and amax_rad_s2 hold one limit
 * per joint, or are NULL for none. On failure *failed_joint (if not NULL) is the first joint that
 * failed (n_joints for a bad duration) and every profile is a rest at its q0. */
traj_status traj_plan_synchronized(traj_profile *profiles, size_t n_joints, traj_kind kind,
                                   const double *q0_rad, const double *qf_rad, double duration_s,
                                   const double *vmax_rad_s, const double *amax_rad_s2,
                                   size_t *failed_joint);

/* The planned move at time t_s (at rest outside [0, T]; a NaN t_s is treated as t_s < 0). */
traj_sample traj_eval(const traj_profile *p, double t_s);

/* A path: n_segments synchronized moves of n_joints joints, segments[i * n_joints + j] being
 * joint j of segment i, segment i starting at start_s[i] (non-decreasing). At time t the segment
 * that started last at or before t is evaluated at t - start_s[i] (the first one before
 * start_s[0]), so contiguous rest-to-rest segments join continuously and a gap is a rest.
 * traj_path_eval writes n_joints samples; traj_path_eval_many writes n_t rows of n_joints
 * (row-major) into each output array that is not NULL. */
void traj_path_eval(const traj_profile *segments, const double *start_s, size_t n_segments,
                    size_t n_joints, double t_s, traj_sample *out);
void traj_path_eval_many(const traj_profile *segments, const double *start_s, size_t n_segments,
                         size_t n_joints, const double *t_s, size_t n_t, double *q_rad,
                         double *qd_rad_s, double *qdd_rad_s2, double *qddd_rad_s3);

#endif
