/* C-level tests of the CRS arm kinematics; built with -Werror and under ASan/UBSan by
 * tests/test_c_core.py. Exit status 0 when every check passes. */
#include <math.h>
#include <stdio.h>

#include "crs_arm.h"

#include "checks.h"

static const double DEG = 3.14159265358979323846 / 180.0;

static void test_known_poses(void)
{
    const double motor_deg[3][3] = {{0, 0, 0}, {0, 90, 0}, {0, 0, -90}};
    const double xyz_in[3][3] = {{10, 0, 20}, {20, 0, 10}, {0, 0, 30}};
    for (int i = 0; i < 3; ++i) {
        double m[3] = {motor_deg[i][0] * DEG, motor_deg[i][1] * DEG, motor_deg[i][2] * DEG};
        double p[3], dh[3], pose[16];
        crs_fk_motor(m, p);
        crs_motor_to_dh(m, dh);
        crs_fk_pose_dh(dh, pose);
        for (int k = 0; k < 3; ++k) {
            check_close("fk_motor", p[k], xyz_in[i][k], 1e-12);
            check_close("fk_pose_dh", pose[4 * k + 3], xyz_in[i][k], 1e-12);
        }
    }
}

static void test_ik_round_trip(void)
{
    int n = 0;
    for (double x = -19.0; x <= 19.0; x += 1.9) {
        for (double z = -5.0; z <= 29.0; z += 1.7) {
            const double p[3] = {x, 0.37 * x - 1.0, z};
            for (int up = 0; up <= 1; ++up) {
                double m[3], back[3];
                if (crs_ik_motor(p, up, m) != CRS_IK_OK) continue;
                crs_fk_motor(m, back);
                for (int k = 0; k < 3; ++k) check_close("fk(ik(p))", back[k], p[k], 1e-9);
                ++n;
            }
        }
    }
    if (n < 200) {
        printf("FAIL only %d reachable samples\n", n);
        ++failures;
    }
}

static void test_unreachable_is_defined(void)
{
    const double far[3] = {0, 0, 31}, centre[3] = {0, 0, 10};
    double m[3];
    if (crs_ik_motor(far, 1, m) != CRS_IK_UNREACHABLE) ++failures;
    for (int k = 0; k < 3; ++k) check_close("unreachable not NaN", isnan(m[k]), 0, 0);
    if (crs_ik_motor(centre, 1, m) != CRS_IK_SHOULDER) ++failures;
    for (int k = 0; k < 3; ++k) check_close("shoulder not NaN", isnan(m[k]), 0, 0);
}

static void test_batch_and_jacobian(void)
{
    double q[6] = {0.1, 0.2, 0.3, -0.4, 1.0, -0.5}, p[6], j[18];
    crs_fk_motor_batch(q, p, 2);
    crs_jacobian_motor_batch(q, j, 2);
    for (int r = 0; r < 2; ++r) {
        for (int c = 0; c < 3; ++c) {
            double qp[3] = {q[3 * r], q[3 * r + 1], q[3 * r + 2]};
            double qm[3] = {q[3 * r], q[3 * r + 1], q[3 * r + 2]};
            double pp[3], pm[3];
            qp[c] += 1e-6;
            qm[c] -= 1e-6;
            crs_fk_motor(qp, pp);
            crs_fk_motor(qm, pm);
            for (int k = 0; k < 3; ++k) {
                check_close("jacobian", j[9 * r + 3 * k + c], (pp[k] - pm[k]) / 2e-6, 1e-6);
            }
        }
    }
}

/* The envelope is the joint bounds and the height of crs_fk_motor: a second implementation of
 * the rule over a grid of motor angles (the envelope computes the height on its own, only when
 * the joint bounds hold), with rows right at the 4 in height. */
static void test_envelope_is_joint_bounds_and_fk_height(void)
{
    int checked = 0, low = 0, mismatched = 0;
    for (int i = -130; i <= 130; i += 10) {
        for (int k = -100; k <= 240; k += 3) {
            for (int m = -200; m <= 200; m += 3) {
                const double motor[3] = {i * DEG, k * DEG, m * DEG};
                double dh[3], xyz[3];
                crs_motor_to_dh(motor, dh);
                crs_fk_motor(motor, xyz);
                const int joints_out = fabs(dh[0]) > CRS_ENVELOPE_TH1_MAX_RAD || dh[1] < CRS_ENVELOPE_TH2_MIN_RAD
                    || dh[1] > CRS_ENVELOPE_TH2_MAX_RAD || dh[2] < CRS_ENVELOPE_TH3_MIN_RAD
                    || dh[2] > CRS_ENVELOPE_TH3_MAX_RAD;
                const int want = joints_out || xyz[2] < CRS_ENVELOPE_Z_MIN_IN;
                low += !joints_out && xyz[2] < CRS_ENVELOPE_Z_MIN_IN;
                mismatched += crs_outside_envelope_motor(motor) != want;
                ++checked;
            }
        }
    }
    /* at the height bound itself: th2M chosen so that z is 4 in to the last bit of its cosine */
    for (int m = 20; m <= 80; m += 10) {
        const double th3m = m * DEG;
        const double c2 = (CRS_ENVELOPE_Z_MIN_IN - CRS_BASE_HEIGHT_IN + CRS_FOREARM_IN * sin(th3m))
                        / CRS_UPPER_ARM_IN;
        if (!(c2 > -1.0 && c2 < 1.0)) continue;
        const double base = acos(c2);
        for (int ulp = -3; ulp <= 3; ++ulp) {
            const double motor[3] = {0.0, base + ulp * 1e-15, th3m};
            double xyz[3];
            crs_fk_motor(motor, xyz);
            double dh[3];
            crs_motor_to_dh(motor, dh);
            const int joints_out = dh[1] < CRS_ENVELOPE_TH2_MIN_RAD || dh[1] > CRS_ENVELOPE_TH2_MAX_RAD
                || dh[2] < CRS_ENVELOPE_TH3_MIN_RAD || dh[2] > CRS_ENVELOPE_TH3_MAX_RAD;
            mismatched += crs_outside_envelope_motor(motor) != (joints_out || xyz[2] < CRS_ENVELOPE_Z_MIN_IN);
            ++checked;
        }
    }
    if (mismatched || low == 0) {
        printf("FAIL envelope vs joint bounds and FK height: %d of %d poses differ, %d below 4 in\n",
               mismatched, checked, low);
        ++failures;
    }
}

int main(void)
{
    test_known_poses();
    test_envelope_is_joint_bounds_and_fk_height();
    test_ik_round_trip();
    test_unreachable_is_defined();
    test_batch_and_jacobian();
    return checks_report();
}
