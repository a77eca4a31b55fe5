#include "traj_profiles.h"

#include <math.h>

static const double TRAJ_PI = 3.14159265358979323846;
/* A planned peak may exceed its limit by this relative amount (rounding at the minimum duration). */
static const double LIMIT_SLACK = 1e-9;

/* Each profile's peak velocity times T/L and peak acceleration times T^2/L when no speed limit
 * binds (Li: 2 and 8; quintic: 15/8 and 10/sqrt(3); cubic: 3/2 and 6; trapezoid with Ta = T/3:
 * 3/2 and 9/2). */
static double shape_vel(traj_kind kind)
{
    switch (kind) {
    case TRAJ_LI: return 2.0;
    case TRAJ_QUINTIC: return 1.875;
    case TRAJ_CUBIC: return 1.5;
    case TRAJ_TRAPEZOID: return 1.5;
    }
    return 0.0;
}

static double shape_acc(traj_kind kind)
{
    switch (kind) {
    case TRAJ_LI: return 8.0;
    case TRAJ_QUINTIC: return 5.77350269189625764509; /* 10/sqrt(3) */
    case TRAJ_CUBIC: return 6.0;
    case TRAJ_TRAPEZOID: return 4.5;
    }
    return 0.0;
}

static int valid_kind(int kind)
{
    return kind == TRAJ_LI || kind == TRAJ_QUINTIC || kind == TRAJ_CUBIC || kind == TRAJ_TRAPEZOID;
}

static int has_limit(double limit)
{
    return limit > 0.0 && isfinite(limit);
}

static int exceeds(double peak, double limit)
{
    return has_limit(limit) && fabs(peak) > limit * (1.0 + LIMIT_SLACK);
}

static void set_rest(traj_profile *p, int kind, double q_rad)
{
    const double q = isfinite(q_rad) ? q_rad : 0.0;
    p->kind = kind;
    p->q0_rad = q;
    p->qf_rad = q;
    p->distance_rad = 0.0;
    p->duration_s = 0.0;
    p->ramp_s = 0.0;
    p->peak_vel_rad_s = 0.0;
    p->peak_acc_rad_s2 = 0.0;
}

static int bad_positions(double q0_rad, double qf_rad)
{
    return !isfinite(q0_rad) || !isfinite(qf_rad) || !isfinite(qf_rad - q0_rad);
}

traj_status traj_plan(traj_profile *p, traj_kind kind, double q0_rad, double qf_rad, double duration_s,
                      double vmax_rad_s, double amax_rad_s2)
{
    set_rest(p, kind, q0_rad);
    if (!valid_kind(kind) || bad_positions(q0_rad, qf_rad) || !(duration_s >= 0.0) || isinf(duration_s)
        || isnan(vmax_rad_s) || isnan(amax_rad_s2)) {
        return TRAJ_BAD_ARGUMENT;
    }
    const double dist = fabs(qf_rad - q0_rad), T = duration_s;
    if (dist == 0.0) {
        p->duration_s = T; /* a rest of that duration */
        return TRAJ_OK;
    }
    if (T == 0.0) return TRAJ_TOO_FAST;

    double vel = shape_vel(kind) * dist / T, ramp = T, acc = shape_acc(kind) * dist / (T * T);
    if (kind == TRAJ_LI || kind == TRAJ_TRAPEZOID) {
        ramp = kind == TRAJ_LI ? 0.5 * T : T / 3.0;
        if (has_limit(vmax_rad_s) && vel > vmax_rad_s) { /* cruise at the limit */
            if (vmax_rad_s * T <= dist) return TRAJ_TOO_FAST;
            vel = vmax_rad_s;
            ramp = T - dist / vel;
        }
        /* Li: V = A Ta / 2 (the ramp's mean acceleration is A/2); trapezoid: V = A Ta */
        acc = (kind == TRAJ_LI ? 2.0 : 1.0) * vel / ramp;
    }
    if (!isfinite(vel) || !isfinite(acc) || !(ramp > 0.0) || exceeds(vel, vmax_rad_s)
        || exceeds(acc, amax_rad_s2)) {
        return TRAJ_TOO_FAST;
    }
    const double sign = qf_rad > q0_rad ? 1.0 : -1.0;
    p->qf_rad = qf_rad;
    p->distance_rad = qf_rad - q0_rad;
    p->duration_s = T;
    p->ramp_s = ramp;
    p->peak_vel_rad_s = sign * vel;
    p->peak_acc_rad_s2 = sign * acc;
    return TRAJ_OK;
}

traj_status traj_min_duration(traj_kind kind, double q0_rad, double qf_rad, double vmax_rad_s,
                              double amax_rad_s2, double *duration_s)
{
    *duration_s = 0.0;
    if (!valid_kind(kind) || bad_positions(q0_rad, qf_rad) || isnan(vmax_rad_s) || isnan(amax_rad_s2)) {
        return TRAJ_BAD_ARGUMENT;
    }
    const double dist = fabs(qf_rad - q0_rad);
    if (dist == 0.0) return TRAJ_OK;
    const int hv = has_limit(vmax_rad_s), ha = has_limit(amax_rad_s2);
    /* The shortest T meeting each limit with the unlimited shape. */
    const double t_vel = hv ? shape_vel(kind) * dist / vmax_rad_s : 0.0;
    const double t_acc = ha ? sqrt(shape_acc(kind) * dist / amax_rad_s2) : 0.0;
    double T = t_vel > t_acc ? t_vel : t_acc;
    if ((kind == TRAJ_LI || kind == TRAJ_TRAPEZOID) && hv && ha && t_acc <= t_vel) {
        /* Shorter than t_vel the cruise is capped at vmax and the ramps shorten as T does,
         * raising the acceleration: the shortest T has ramps of exactly amax, Ta = k vmax/amax
         * (k = 2 for Li, 1 for the trapezoid), and T = L/vmax + Ta. */
        const double k = kind == TRAJ_LI ? 2.0 : 1.0;
        T = dist / vmax_rad_s + k * vmax_rad_s / amax_rad_s2;
    }
    *duration_s = T;
    return TRAJ_OK;
}

traj_status traj_plan_synchronized(traj_profile *profiles, size_t n_joints, traj_kind kind,
                                   const double *q0_rad, const double *qf_rad, double duration_s,
                                   const double *vmax_rad_s, const double *amax_rad_s2,
                                   size_t *failed_joint)
{
    traj_status status = TRAJ_OK;
    size_t j = n_joints; /* "no joint in particular" for a bad duration */
    if (!(duration_s >= 0.0) || isinf(duration_s)) {
        status = TRAJ_BAD_ARGUMENT;
        goto fail;
    }
    /* every joint in duration_s, if each can */
    for (j = 0; j < n_joints; ++j) {
        status = traj_plan(&profiles[j], kind, q0_rad[j], qf_rad[j], duration_s,
                           vmax_rad_s ? vmax_rad_s[j] : 0.0, amax_rad_s2 ? amax_rad_s2[j] : 0.0);
        if (status != TRAJ_OK) break;
    }
    if (status == TRAJ_OK) return TRAJ_OK;
    if (status == TRAJ_BAD_ARGUMENT) goto fail;
    /* else as long as the slowest joint needs */
    double T = duration_s;
    for (j = 0; j < n_joints; ++j) {
        double t_min;
        status = traj_min_duration(kind, q0_rad[j], qf_rad[j], vmax_rad_s ? vmax_rad_s[j] : 0.0,
                                   amax_rad_s2 ? amax_rad_s2[j] : 0.0, &t_min);
        if (status != TRAJ_OK) goto fail;
        if (t_min > T) T = t_min;
    }
    for (j = 0; j < n_joints; ++j) {
        status = traj_plan(&profiles[j], kind, q0_rad[j], qf_rad[j], T, vmax_rad_s ? vmax_rad_s[j] : 0.0,
                           amax_rad_s2 ? amax_rad_s2[j] : 0.0);
        if (status != TRAJ_OK) goto fail;
    }
    return TRAJ_OK;
fail:
    for (size_t i = 0; i < n_joints; ++i) set_rest(&profiles[i], kind, q0_rad[i]);
    if (failed_joint) *failed_joint = j;
    return status;
}

/* The move's first half seen from its nearer end: u in [0, T/2] seconds from that end gives the
 * displacement from that end and the derivatives, in the direction of travel. Every profile here
 * is point-symmetric about its midpoint, so the second half is q = qf - dq(T - t),
 * qd = v(T - t), qdd = -a(T - t), jerk = j(T - t). */
typedef struct {
    double dq, v, a, j;
} half_sample;

static half_sample li_ramp(double A, double Ta, double u)
{
    /* acceleration (A/2)(1 - cos x) = A sin^2(x/2) with x = 2 pi u/Ta */
    const double x = 2.0 * TRAJ_PI * u / Ta, n = Ta / (2.0 * TRAJ_PI);
    const double sh = sin(0.5 * x);
    half_sample h;
    h.j = A * TRAJ_PI / Ta * sin(x);
    h.a = A * sh * sh;
    h.v = 0.5 * A * (u - n * sin(x));
    h.dq = 0.5 * A * (0.5 * u * u - 2.0 * n * n * sh * sh);
    return h;
}

static half_sample first_half(const traj_profile *p, double u)
{
    const double T = p->duration_s, L = p->distance_rad;
    const double Ta = p->ramp_s, V = p->peak_vel_rad_s, A = p->peak_acc_rad_s2;
    const double s = u / T;
    half_sample h = {0.0, 0.0, 0.0, 0.0};
    switch (p->kind) {
    case TRAJ_LI:
        if (u <= Ta) return li_ramp(A, Ta, u);
        h.dq = 0.25 * A * Ta * Ta + V * (u - Ta);
        h.v = V;
        return h;
    case TRAJ_TRAPEZOID:
        if (u < Ta) {
            h.dq = 0.5 * A * u * u;
            h.v = A * u;
            h.a = A;
        } else {
            h.dq = 0.5 * A * Ta * Ta + V * (u - Ta);
            h.v = V;
        }
        return h;
    case TRAJ_QUINTIC:
        h.dq = L * s * s * s * (10.0 + s * (-15.0 + 6.0 * s));
        h.v = 30.0 * L * s * s * (1.0 - s) * (1.0 - s) / T;
        h.a = 60.0 * L * s * (1.0 - s) * (1.0 - 2.0 * s) / (T * T);
        h.j = 60.0 * L * (1.0 + s * (-6.0 + 6.0 * s)) / (T * T * T);
        return h;
    case TRAJ_CUBIC:
        h.dq = L * s * s * (3.0 - 2.0 * s);
        h.v = 6.0 * L * s * (1.0 - s) / T;
        h.a = 6.0 * L * (1.0 - 2.0 * s) / (T * T);
        h.j = -12.0 * L / (T * T * T);
        return h;
    }
    return h;
}

traj_sample traj_eval(const traj_profile *p, double t_s)
{
    traj_sample out = {p->q0_rad, 0.0, 0.0, 0.0};
    const double T = p->duration_s;
    if (!(t_s >= 0.0) || p->distance_rad == 0.0) return out;
    if (t_s > T) {
        out.q_rad = p->qf_rad;
        return out;
    }
    const int second_half = t_s > 0.5 * T;
    const half_sample h = first_half(p, second_half ? T - t_s : t_s);
    out.q_rad = second_half ? p->qf_rad - h.dq : p->q0_rad + h.dq;
    out.qd_rad_s = h.v;
    out.qdd_rad_s2 = second_half ? -h.a : h.a;
    out.qddd_rad_s3 = h.j;
    return out;
}

/* The segment that started last at or before t (0 before the first one). */
static size_t segment_at(const double *start_s, size_t n_segments, double t_s)
{
    size_t lo = 0, hi = n_segments; /* answer in [lo, hi) once start_s[lo] <= t */
    if (n_segments == 0 || !(t_s >= start_s[0])) return 0;
    while (hi - lo > 1) {
        const size_t mid = lo + (hi - lo) / 2;
        if (start_s[mid] <= t_s) lo = mid;
        else hi = mid;
    }
    return lo;
}

void traj_path_eval(const traj_profile *segments, const double *start_s, size_t n_segments,
                    size_t n_joints, double t_s, traj_sample *out)
{
    if (n_segments == 0) return;
    const size_t i = segment_at(start_s, n_segments, t_s);
    for (size_t j = 0; j < n_joints; ++j) out[j] = traj_eval(&segments[i * n_joints + j], t_s - start_s[i]);
}

void traj_path_eval_many(const traj_profile *segments, const double *start_s, size_t n_segments,
                         size_t n_joints, const double *t_s, size_t n_t, double *q_rad,
                         double *qd_rad_s, double *qdd_rad_s2, double *qddd_rad_s3)
{
    if (n_segments == 0) return;
    for (size_t k = 0; k < n_t; ++k) {
        const size_t i = segment_at(start_s, n_segments, t_s[k]);
        const double local = t_s[k] - start_s[i];
        for (size_t j = 0; j < n_joints; ++j) {
            const traj_sample s = traj_eval(&segments[i * n_joints + j], local);
            const size_t at = k * n_joints + j;
            if (q_rad) q_rad[at] = s.q_rad;
            if (qd_rad_s) qd_rad_s[at] = s.qd_rad_s;
            if (qdd_rad_s2) qdd_rad_s2[at] = s.qdd_rad_s2;
            if (qddd_rad_s3) qddd_rad_s3[at] = s.qddd_rad_s3;
        }
    }
}
