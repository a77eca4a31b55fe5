/* Numerical inverse kinematics of any DH chain (chain.h): damped least squares with a
 * Levenberg-Marquardt damping schedule, joint limits kept by projection, and random restarts.
 *
 * The error of a configuration q against a target pose T* (chain unit, rad, world frame) is
 *   e = (p* - p(q), log(R* R(q)^T))   (full pose; the second part is a rotation vector), or
 *   e = p* - p(q)                      (position only),
 * and the residual is |e| (Euclidean norm). A solve succeeds when the residual is at most the
 * tolerance with every joint inside its limits. Random starts are drawn uniformly inside the
 * limits ([-pi, pi] for an unlimited joint) from a generator seeded by (seed, row index), so a
 * row's answer does not depend on the other rows of the batch.
 */
#ifndef CRSLAB_CHAIN_IK_H
#define CRSLAB_CHAIN_IK_H

#include <stddef.h>

#include "chain.h"

typedef struct {
    int max_iterations;      /* LM iterations per start (each costs one FK and Jacobian) */
    int max_restarts;        /* random starts after the first one */
    double tolerance;        /* residual to reach (chain unit and rad) */
    int position_only;       /* 1: match the target's position only; 0: the full pose */
    unsigned long long seed; /* of the random starts */
} chain_ik_options;

/* Solve n targets. target is n x 16 (row-major poses; only the translation is read when
 * position_only). q0 (n x joints) is the first start of each row, or NULL for a random one.
 * lower and upper (joints) are the limits in rad, or NULL for none; infinite entries are allowed.
 * Outputs per row: q (n x joints; the best configuration found when the solve failed), success
 * (0/1), iterations (all starts together), restarts (starts after the first) and residual. */
void chain_ik_batch(const dh_chain *c, const double *lower, const double *upper, const chain_ik_options *opt,
                    const double *target, const double *q0, double *q, int *success, int *iterations,
                    int *restarts, double *residual, size_t n);

#endif
