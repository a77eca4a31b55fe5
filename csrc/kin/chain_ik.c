#include "chain_ik.h"

#include <math.h>
#include <string.h>

#include "rotation.h"

static const double PI = 3.14159265358979323846;
/* Damping schedule: start, floor, and the value past which a start is judged stuck. */
static const double LAMBDA_START = 1e-2, LAMBDA_FLOOR = 1e-12, LAMBDA_STUCK = 1e6;
/* Stall test: a start must cut its squared error by this factor every STALL_WINDOW iterations. */
static const double STALL_FACTOR = 0.5;
enum { STALL_WINDOW = 8 };

/* splitmix64: a small, well-mixed generator whose whole state is one integer on the stack. */
static unsigned long long next_random(unsigned long long *state)
{
    unsigned long long z = (*state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

static double uniform(unsigned long long *state, double lo, double hi)
{
    const double u = (double)(next_random(state) >> 11) * 0x1.0p-53;
    return lo + (hi - lo) * u;
}

/* Finite bounds of joint j for sampling: its limits, or [-pi, pi] where there is none. */
static void sample_range(const double *lower, const double *upper, int j, double *lo, double *hi)
{
    *lo = (lower && isfinite(lower[j])) ? lower[j] : -PI;
    *hi = (upper && isfinite(upper[j])) ? upper[j] : PI;
    if (*hi < *lo) *hi = *lo;
}

static void clamp_to_limits(const double *lower, const double *upper, int nj, double *q)
{
    for (int j = 0; j < nj; ++j) {
        if (lower && q[j] < lower[j]) q[j] = lower[j];
        if (upper && q[j] > upper[j]) q[j] = upper[j];
    }
}

/* Error vector (3 or 6 entries) of pose against target; returns its squared norm. */
static double pose_error(const double target[16], const double pose[16], int position_only, double *e)
{
    for (int r = 0; r < 3; ++r) e[r] = target[4 * r + 3] - pose[4 * r + 3];
    double sq = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
    if (position_only) return sq;
    /* R* R^T, then its rotation vector */
    double rel[9], axis[3], angle;
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            rel[3 * i + k] = target[4 * i] * pose[4 * k] + target[4 * i + 1] * pose[4 * k + 1]
                             + target[4 * i + 2] * pose[4 * k + 2];
        }
    }
    rot_matrix_to_axis_angle(rel, axis, &angle);
    for (int r = 0; r < 3; ++r) {
        e[3 + r] = angle * axis[r];
        sq += e[3 + r] * e[3 + r];
    }
    return sq;
}

/* Solve (J^T J + lambda I) dq = J^T e by Cholesky over the free joints (a joint with
 * free[j] == 0 keeps dq[j] = 0); m equations (3 or 6), nj unknowns. J is 6 x nj row-major (only
 * its first m rows are used). Returns 0 if the system is not positive definite (it cannot be for
 * lambda > 0 and finite entries, but is checked). */
static int damped_step(const double *jac, const double *e, const int *free, int m, int nj, double lambda,
                       double *dq)
{
    double a[CHAIN_MAX_ROWS * CHAIN_MAX_ROWS], g[CHAIN_MAX_ROWS];
    for (int i = 0; i < nj; ++i) {
        double gi = 0.0;
        for (int r = 0; r < m; ++r) gi += jac[r * nj + i] * e[r];
        g[i] = free[i] ? gi : 0.0;
        for (int k = 0; k <= i; ++k) {
            double s = 0.0;
            if (free[i] && free[k]) {
                for (int r = 0; r < m; ++r) s += jac[r * nj + i] * jac[r * nj + k];
            }
            a[i * nj + k] = s + (i == k ? (free[i] ? lambda : 1.0) : 0.0);
        }
    }
    for (int i = 0; i < nj; ++i) { /* lower-triangular L with L L^T = A, in place */
        for (int k = 0; k <= i; ++k) {
            double s = a[i * nj + k];
            for (int p = 0; p < k; ++p) s -= a[i * nj + p] * a[k * nj + p];
            if (i == k) {
                if (!(s > 0.0)) return 0;
                a[i * nj + i] = sqrt(s);
            } else {
                a[i * nj + k] = s / a[k * nj + k];
            }
        }
    }
    for (int i = 0; i < nj; ++i) { /* L y = g */
        double s = g[i];
        for (int p = 0; p < i; ++p) s -= a[i * nj + p] * dq[p];
        dq[i] = s / a[i * nj + i];
    }
    for (int i = nj - 1; i >= 0; --i) { /* L^T dq = y */
        double s = dq[i];
        for (int p = i + 1; p < nj; ++p) s -= a[p * nj + i] * dq[p];
        dq[i] = s / a[i * nj + i];
    }
    return 1;
}

typedef struct {
    int success, iterations, restarts;
    double residual;
} solve_result;

static solve_result solve_one(const dh_chain *c, const chain_constants *k, const double *lower,
                              const double *upper, const chain_ik_options *opt, const double target[16],
                              const double *q0, unsigned long long state, double *q_best)
{
    const int nj = k->n_joints, m = opt->position_only ? 3 : 6;
    const double tol_sq = opt->tolerance * opt->tolerance;
    double q[CHAIN_MAX_ROWS], q_try[CHAIN_MAX_ROWS], dq[CHAIN_MAX_ROWS];
    double jac[6 * CHAIN_MAX_ROWS], jac_try[6 * CHAIN_MAX_ROWS], pose[16], e[6], e_try[6];
    double best_sq = INFINITY;
    solve_result res = {0, 0, 0, INFINITY};
    for (int start = 0; start <= opt->max_restarts; ++start) {
        for (int j = 0; j < nj; ++j) {
            double lo, hi;
            sample_range(lower, upper, j, &lo, &hi);
            q[j] = (start == 0 && q0) ? q0[j] : uniform(&state, lo, hi);
        }
        clamp_to_limits(lower, upper, nj, q);
        res.restarts = start;
        chain_pose_jacobian(c, k, q, pose, jac);
        double cost = pose_error(target, pose, opt->position_only, e);
        double lambda = LAMBDA_START, checkpoint = cost;
        for (int it = 0; it < opt->max_iterations && cost > tol_sq && lambda < LAMBDA_STUCK; ++it) {
            /* a start whose squared error has not fallen by STALL_FACTOR over STALL_WINDOW
             * iterations sits in a local minimum (often on a limit): restart instead */
            if (it > 0 && it % STALL_WINDOW == 0) {
                if (cost > STALL_FACTOR * checkpoint) break;
                checkpoint = cost;
            }
            ++res.iterations;
            /* joints resting on a limit that the step would push further out are held there,
             * and the step is solved again over the others (a projected LM step) */
            int free[CHAIN_MAX_ROWS], ok = 1;
            for (int j = 0; j < nj; ++j) free[j] = 1;
            for (int pass = 0; pass < nj && ok; ++pass) {
                ok = damped_step(jac, e, free, m, nj, lambda, dq);
                int held = 0;
                for (int j = 0; j < nj; ++j) {
                    const int at_low = lower && q[j] <= lower[j] && dq[j] < 0.0;
                    const int at_high = upper && q[j] >= upper[j] && dq[j] > 0.0;
                    if (free[j] && (at_low || at_high)) {
                        free[j] = 0;
                        held = 1;
                    }
                }
                if (!held) break;
            }
            if (!ok) break;
            for (int j = 0; j < nj; ++j) q_try[j] = q[j] + dq[j];
            clamp_to_limits(lower, upper, nj, q_try);
            chain_pose_jacobian(c, k, q_try, pose, jac_try);
            const double cost_try = pose_error(target, pose, opt->position_only, e_try);
            if (cost_try < cost) { /* accept: trust the linear model more */
                cost = cost_try;
                memcpy(q, q_try, sizeof(double) * (size_t)nj);
                memcpy(jac, jac_try, sizeof(double) * 6 * (size_t)nj);
                memcpy(e, e_try, sizeof e);
                lambda = lambda * 0.1 > LAMBDA_FLOOR ? lambda * 0.1 : LAMBDA_FLOOR;
            } else { /* reject: damp harder */
                lambda *= 10.0;
            }
        }
        if (cost < best_sq) {
            best_sq = cost;
            memcpy(q_best, q, sizeof(double) * (size_t)nj);
        }
        if (cost <= tol_sq) {
            res.success = 1;
            break;
        }
    }
    res.residual = sqrt(best_sq);
    /* a joint is reported in [-pi, pi] whenever that turn of it is inside its limits */
    for (int j = 0; j < nj; ++j) {
        const double w = remainder(q_best[j], 2.0 * PI);
        if ((!lower || w >= lower[j]) && (!upper || w <= upper[j])) q_best[j] = w;
    }
    return res;
}

void chain_ik_batch(const dh_chain *c, const double *lower, const double *upper, const chain_ik_options *opt,
                    const double *target, const double *q0, double *q, int *success, int *iterations,
                    int *restarts, double *residual, size_t n)
{
    chain_constants k;
    chain_prepare(c, &k);
    const size_t nj = (size_t)k.n_joints;
    for (size_t i = 0; i < n; ++i) {
        unsigned long long state = opt->seed ^ (0xD1B54A32D192ED03ULL * (unsigned long long)(i + 1));
        const solve_result r = solve_one(c, &k, lower, upper, opt, target + 16 * i, q0 ? q0 + nj * i : NULL,
                                         state, q + nj * i);
        success[i] = r.success;
        iterations[i] = r.iterations;
        restarts[i] = r.restarts;
        residual[i] = r.residual;
    }
}
