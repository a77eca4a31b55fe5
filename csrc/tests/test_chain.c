/* C-level tests of DH chains, rotations, closed-form and numerical IK; built with -Werror and
 * under ASan/UBSan by tests/test_c_core.py. Exit status 0 when every check passes. */
#include <math.h>
#include <stdio.h>

#include "chain.h"
#include "chain_ik.h"
#include "closed_ik.h"
#include "dh.h"
#include "rotation.h"

#include "checks.h"

static const double PI = 3.14159265358979323846;

/* Seed 002's Panda: standard DH, 8 rows (the first fixed), and its joint-centre offsets. */
static const double PANDA_A[8] = {0, 0, 0, 0.0825, 0.0825, 0, 0.088, 0};
static const double PANDA_ALPHA[8] = {0, -PI / 2, PI / 2, PI / 2, PI / 2, -PI / 2, PI / 2, 0};
static const double PANDA_D[8] = {0.141, 0.192, 0, 0.316, 0, 0.384, 0, 0.21};
static const double PANDA_THETA[8] = {0, 0, 0, 0, PI, 0, -PI, -PI / 4};
static const int PANDA_TYPE[8] = {CHAIN_FIXED, 0, 0, 0, 0, 0, 0, 0};
static const double PANDA_CENTRE[24] = {0, 0, 0, 0, 0, 0, 0, 0, 0.195, 0, 0, 0,
                                        0, 0, 0.125, 0, 0, -0.015, 0, 0, 0.051, 0, 0, 0};
static const double PANDA_LOWER[7] = {-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973};
static const double PANDA_UPPER[7] = {2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973};
/* The same arm in Franka's modified table, ending at the seed's end effector (fixed last row). */
static const double MDH_A[8] = {0, 0, 0, 0.0825, -0.0825, 0, 0.088, 0};
static const double MDH_ALPHA[8] = {0, -PI / 2, PI / 2, PI / 2, -PI / 2, PI / 2, PI / 2, 0};
static const double MDH_D[8] = {0.333, 0, 0.316, 0, 0.384, 0, 0, 0.21};
static const double MDH_THETA[8] = {0, 0, 0, 0, 0, 0, 0, -PI / 4};
static const int MDH_TYPE[8] = {0, 0, 0, 0, 0, 0, 0, CHAIN_FIXED};

static dh_chain panda_standard(void)
{
    const dh_chain c = {8, CHAIN_STANDARD, PANDA_A, PANDA_ALPHA, PANDA_D, PANDA_THETA, PANDA_TYPE, NULL, NULL};
    return c;
}

static void test_panda_seed_002(void)
{
    const dh_chain c = panda_standard();
    const double q[7] = {0, 0, 0, -PI / 2, 0, PI / 2, PI / 4};
    const double want_pose[16] = {1, 0, 0, 0.5545, 0, -1, 0, 0, 0, 0, -1, 0.5215, 0, 0, 0, 1};
    const double want_centres[24] = {0, 0, 0.141, 0, 0, 0.333, 0, 0, 0.528, 0.0825, 0, 0.649,
                                     0.2075, 0, 0.7315, 0.4665, 0.015, 0.7315, 0.5545, 0, 0.6805,
                                     0.5545, 0, 0.5215};
    double pose[16], centres[24];
    check("panda table is valid", chain_check(&c) == CHAIN_OK && chain_joint_count(&c) == 7);
    chain_fk_batch(&c, q, pose, 1);
    for (int i = 0; i < 16; ++i) check_close("panda seed pose", pose[i], want_pose[i], 1e-12);
    chain_points_batch(&c, q, PANDA_CENTRE, centres, 1);
    for (int i = 0; i < 24; ++i) check_close("panda seed joint centre", centres[i], want_centres[i], 1e-12);
}

/* FK by 4x4 products of dh_standard_transform / dh_modified_transform, for comparison. */
static void product_fk(const dh_chain *c, const double *q, double out[16])
{
    double t[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, a[16], next[16];
    for (int i = 0, j = 0; i < c->n_rows; ++i) {
        const double theta = c->theta_rad[i] + (c->joint_type[i] == CHAIN_REVOLUTE ? q[j++] : 0.0);
        if (c->convention == CHAIN_MODIFIED) {
            dh_modified_transform(c->a[i], c->alpha_rad[i], c->d[i], theta, a);
        } else {
            dh_standard_transform(c->a[i], c->alpha_rad[i], c->d[i], theta, a);
        }
        mat4_mul(t, a, next);
        for (int k = 0; k < 16; ++k) t[k] = next[k];
    }
    for (int k = 0; k < 16; ++k) out[k] = t[k];
}

static void test_conventions_agree_and_match_products(void)
{
    const dh_chain std = panda_standard();
    const dh_chain mdh = {8, CHAIN_MODIFIED, MDH_A, MDH_ALPHA, MDH_D, MDH_THETA, MDH_TYPE, NULL, NULL};
    double q[7 * 50], ps[16 * 50], pm[16 * 50], prod[16];
    for (int k = 0; k < 7 * 50; ++k) q[k] = sin(1.7 * k + 0.3) * 2.5;
    chain_fk_batch(&std, q, ps, 50);
    chain_fk_batch(&mdh, q, pm, 50);
    for (int n = 0; n < 50; ++n) {
        product_fk(&std, q + 7 * n, prod);
        for (int i = 0; i < 16; ++i) {
            check_close("standard vs modified", ps[16 * n + i], pm[16 * n + i], 1e-12);
            check_close("batch vs 4x4 products", ps[16 * n + i], prod[i], 1e-12);
        }
    }
}

static void test_jacobian_by_differences(void)
{
    const dh_chain c = panda_standard();
    chain_constants k;
    chain_prepare(&c, &k);
    const double q[7] = {0.3, -0.5, 1.1, -1.7, 0.4, 1.9, -0.6};
    double pose[16], jac[42];
    chain_pose_jacobian(&c, &k, q, pose, jac);
    for (int j = 0; j < 7; ++j) {
        double qp[7], qm[7], tp[16], tm[16];
        for (int i = 0; i < 7; ++i) qp[i] = qm[i] = q[i];
        qp[j] += 1e-6;
        qm[j] -= 1e-6;
        chain_fk_batch(&c, qp, tp, 1);
        chain_fk_batch(&c, qm, tm, 1);
        for (int r = 0; r < 3; ++r) {
            check_close("jacobian linear", jac[r * 7 + j], (tp[4 * r + 3] - tm[4 * r + 3]) / 2e-6, 1e-7);
        }
    }
}

static void test_rotations(void)
{
    const double zyx[3] = {0.4, -1.2, 2.5};
    double r[9], back[3], r2[9], axis[3], angle;
    rot_euler_zyx_to_matrix(zyx, r);
    check("euler matrix is a rotation", rot_check(r, ROT_CHECK_TOL, NULL) == ROT_OK);
    check("regular case", rot_matrix_to_euler_zyx(r, back) == 0);
    for (int i = 0; i < 3; ++i) check_close("euler round trip", back[i], zyx[i], 1e-12);
    const double lock[3] = {0.7, PI / 2, 0.2};
    rot_euler_zyx_to_matrix(lock, r);
    check("gimbal lock flagged", rot_matrix_to_euler_zyx(r, back) == 1);
    check_close("gimbal lock alpha", back[0], 0.0, 0.0);
    rot_euler_zyx_to_matrix(back, r2);
    for (int i = 0; i < 9; ++i) check_close("gimbal lock matrix", r2[i], r[i], 1e-12);
    const double n[3] = {1, 2, -2};
    check("axis-angle", rot_axis_angle_to_matrix(n, PI - 1e-9, r) == ROT_OK);
    rot_matrix_to_axis_angle(r, axis, &angle);
    check_close("near pi angle", angle, PI - 1e-9, 1e-9);
    check_close("near pi axis", fabs(axis[0] * n[0] + axis[1] * n[1] + axis[2] * n[2]) / 3.0, 1.0, 1e-9);
    const double reflect[9] = {1, 0, 0, 0, 1, 0, 0, 0, -1}, zero[3] = {0, 0, 0};
    check("reflection refused", rot_check(reflect, ROT_CHECK_TOL, NULL) == ROT_REFLECTION);
    check("zero axis refused", rot_axis_angle_to_matrix(zero, 1.0, r) == ROT_ZERO_AXIS);
}

static void test_closed_forms(void)
{
    const double dims[4] = {0, 10, 5, 5}, lo[3] = {-PI, -PI / 2, -PI}, hi[3] = {PI, PI / 2, PI};
    const double q_true[3] = {2.4, 0.3, -1.1};
    const double reach = 10 + 5 * cos(q_true[1]) + 5 * cos(q_true[1] + q_true[2]);
    const double p[3] = {reach * cos(q_true[0]), reach * sin(q_true[0]),
                         5 * sin(q_true[1]) + 5 * sin(q_true[1] + q_true[2])};
    double q[12];
    int status[4], found = 0;
    check("rrr regular", rrr_ik(dims, lo, hi, p, q, status) == IK_SINGULAR_NONE);
    for (int s = 0; s < 4; ++s) {
        if (status[s] != IK_SLOT_OK) continue;
        const double r = 10 + 5 * cos(q[3 * s + 1]) + 5 * cos(q[3 * s + 1] + q[3 * s + 2]);
        check_close("rrr x", r * cos(q[3 * s]), p[0], 1e-9);
        check_close("rrr y", r * sin(q[3 * s]), p[1], 1e-9);
        found |= fabs(q[3 * s] - q_true[0]) < 1e-9 && fabs(q[3 * s + 1] - q_true[1]) < 1e-9
                 && fabs(q[3 * s + 2] - q_true[2]) < 1e-9;
    }
    check("rrr finds the source configuration", found);
    const double links[3] = {1, 1, 0.5}, target[3] = {1, 1.5, PI / 2};
    double qp[6];
    int sp[2];
    planar3r_ik(links, NULL, NULL, target, qp, sp);
    check("planar both elbows", sp[0] == IK_SLOT_OK && sp[1] == IK_SLOT_OK);
    check_close("planar elbow q2", qp[1], PI / 2, 1e-12);
    const double far[3] = {0, 0, 40};
    rrr_ik(dims, lo, hi, far, q, status);
    for (int s = 0; s < 4; ++s) {
        check("rrr far is unreachable", status[s] == IK_SLOT_UNREACHABLE && !isnan(q[3 * s + 1]));
    }
}

static void test_numerical_ik(void)
{
    const dh_chain c = panda_standard();
    const chain_ik_options opt = {60, 50, 1e-9, 0, 12345ULL};
    double q_true[7 * 8], targets[16 * 8], q[7 * 8], residual[8];
    int success[8], iterations[8], restarts[8];
    for (int n = 0; n < 8; ++n) {
        for (int j = 0; j < 7; ++j) {
            const double u = 0.5 + 0.45 * sin(3.1 * n + 1.3 * j);
            q_true[7 * n + j] = PANDA_LOWER[j] + u * (PANDA_UPPER[j] - PANDA_LOWER[j]);
        }
    }
    chain_fk_batch(&c, q_true, targets, 8);
    chain_ik_batch(&c, PANDA_LOWER, PANDA_UPPER, &opt, targets, NULL, q, success, iterations, restarts, residual,
                   8);
    for (int n = 0; n < 8; ++n) {
        double pose[16];
        check("numerical ik success", success[n] == 1 && residual[n] <= 1e-9);
        chain_fk_batch(&c, q + 7 * n, pose, 1);
        for (int i = 0; i < 16; ++i) check_close("fk(ik(T)) = T", pose[i], targets[16 * n + i], 1e-8);
        for (int j = 0; j < 7; ++j) {
            check("within limits", q[7 * n + j] >= PANDA_LOWER[j] && q[7 * n + j] <= PANDA_UPPER[j]);
        }
    }
}

static void test_bad_tables(void)
{
    const int bad_type[1] = {7};
    const double one[1] = {1.0}, nan_value[1] = {NAN};
    const dh_chain empty = {0, CHAIN_STANDARD, one, one, one, one, PANDA_TYPE, NULL, NULL};
    const dh_chain typed = {1, CHAIN_STANDARD, one, one, one, one, bad_type, NULL, NULL};
    const dh_chain nan_row = {1, CHAIN_MODIFIED, nan_value, one, one, one, PANDA_TYPE + 1, NULL, NULL};
    const dh_chain missing = {1, CHAIN_STANDARD, NULL, one, one, one, PANDA_TYPE, NULL, NULL};
    check("no rows", chain_check(&empty) == CHAIN_BAD_ROW_COUNT);
    check("bad joint type", chain_check(&typed) == CHAIN_BAD_JOINT_TYPE);
    check("NaN entry", chain_check(&nan_row) == CHAIN_NOT_FINITE);
    check("missing column", chain_check(&missing) == CHAIN_NULL_TABLE);
}

int main(void)
{
    test_panda_seed_002();
    test_conventions_agree_and_match_products();
    test_jacobian_by_differences();
    test_rotations();
    test_closed_forms();
    test_numerical_ik();
    test_bad_tables();
    return checks_report();
}
