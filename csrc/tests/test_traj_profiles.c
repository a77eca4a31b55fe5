/* C-level tests of the trajectory profiles; built with -Werror and under ASan/UBSan by
 * tests/test_c_core.py. Exit status 0 when every check passes. */
#include <math.h>
#include <stdio.h>

#include "traj_profiles.h"

#include "checks.h"

static const traj_kind KINDS[4] = {TRAJ_LI, TRAJ_QUINTIC, TRAJ_CUBIC, TRAJ_TRAPEZOID};
static const char *const NAMES[4] = {"li", "quintic", "cubic", "trapezoid"};

/* Every profile starts and ends at rest at its end points; Li and quintic also with zero
 * acceleration, and Li with zero jerk. */
static void test_boundary_conditions(void)
{
    for (int k = 0; k < 4; ++k) {
        traj_profile p;
        const double q0 = 0.3, qf = -1.2, T = 1.7;
        check("plan ok", traj_plan(&p, KINDS[k], q0, qf, T, 0.0, 0.0) == TRAJ_OK);
        const traj_sample a = traj_eval(&p, 0.0), b = traj_eval(&p, T);
        check_close(NAMES[k], a.q_rad, q0, 0.0);
        check_close(NAMES[k], b.q_rad, qf, 0.0);
        check_close(NAMES[k], a.qd_rad_s, 0.0, 1e-15);
        check_close(NAMES[k], b.qd_rad_s, 0.0, 1e-15);
        if (KINDS[k] == TRAJ_LI || KINDS[k] == TRAJ_QUINTIC) {
            check_close(NAMES[k], a.qdd_rad_s2, 0.0, 1e-14);
            check_close(NAMES[k], b.qdd_rad_s2, 0.0, 1e-14);
        }
        if (KINDS[k] == TRAJ_LI) {
            check_close("li jerk at 0", a.qddd_rad_s3, 0.0, 1e-14);
            check_close("li jerk at T", b.qddd_rad_s3, 0.0, 1e-13);
        }
        /* clamped outside [0, T] */
        const traj_sample before = traj_eval(&p, -3.0), after = traj_eval(&p, T + 5.0);
        check_close("rest before", before.q_rad, q0, 0.0);
        check_close("rest after", after.q_rad, qf, 0.0);
        check("at rest", before.qd_rad_s == 0.0 && after.qdd_rad_s2 == 0.0 && after.qddd_rad_s3 == 0.0);
    }
}

/* Li without a cruise: peak velocity 2L/T at T/2, peak acceleration 8L/T^2 at T/4, peak jerk
 * 8 pi A/T at 0+ (A pi/Ta with Ta = T/2, a quarter of the way into the ramp: jerk = A pi/Ta). */
static void test_li_peaks(void)
{
    traj_profile p;
    const double L = 2.5, T = 2.0;
    traj_plan(&p, TRAJ_LI, 1.0, 1.0 + L, T, 0.0, 0.0);
    check_close("li peak velocity", traj_eval(&p, 0.5 * T).qd_rad_s, 2.0 * L / T, 1e-12);
    check_close("li peak acceleration", traj_eval(&p, 0.25 * T).qdd_rad_s2, 8.0 * L / (T * T), 1e-12);
    check_close("li ramp is T/2", p.ramp_s, 0.5 * T, 0.0);
    check_close("li midpoint", traj_eval(&p, 0.5 * T).q_rad, 1.0 + 0.5 * L, 1e-12);
    /* jerk (A pi/Ta) sin(2 pi t/Ta) peaks at t = Ta/4 */
    const double A = 8.0 * L / (T * T), Ta = 0.5 * T;
    check_close("li peak jerk", traj_eval(&p, 0.25 * Ta).qddd_rad_s3, A * 3.14159265358979323846 / Ta, 1e-9);
}

/* Velocity is the derivative of position, acceleration of velocity, jerk of acceleration
 * (central differences), away from the trapezoid's acceleration jumps. */
static void test_derivatives(void)
{
    const double h = 1e-6;
    for (int k = 0; k < 4; ++k) {
        for (int capped = 0; capped <= 1; ++capped) {
            traj_profile p;
            const double q0 = -0.4, qf = 0.9, T = 1.3, L = qf - q0;
            /* capped: the speed limit is 80 % of the unlimited peak, so Li and trapezoid cruise */
            const double vmax = capped ? 0.8 * (KINDS[k] == TRAJ_LI ? 2.0 : 1.5) * L / T : 0.0;
            if (capped && (KINDS[k] == TRAJ_QUINTIC || KINDS[k] == TRAJ_CUBIC)) continue;
            check("plan ok", traj_plan(&p, KINDS[k], q0, qf, T, vmax, 0.0) == TRAJ_OK);
            for (int i = 1; i < 100; ++i) {
                const double t = T * i / 100.0 + 1e-4;
                if (KINDS[k] == TRAJ_TRAPEZOID
                    && (fabs(t - p.ramp_s) < 1e-3 || fabs(t - (T - p.ramp_s)) < 1e-3)) {
                    continue;
                }
                const traj_sample m = traj_eval(&p, t - h), c = traj_eval(&p, t), n = traj_eval(&p, t + h);
                check_close(NAMES[k], (n.q_rad - m.q_rad) / (2 * h), c.qd_rad_s, 1e-6);
                check_close(NAMES[k], (n.qd_rad_s - m.qd_rad_s) / (2 * h), c.qdd_rad_s2, 1e-5);
                check_close(NAMES[k], (n.qdd_rad_s2 - m.qdd_rad_s2) / (2 * h), c.qddd_rad_s3, 1e-4);
            }
        }
    }
}

/* With a cruise phase every phase change is continuous in position, velocity and acceleration. */
static void test_li_cruise_phase_changes(void)
{
    traj_profile p;
    const double L = 1.0, T = 2.0, vmax = 0.6; /* unlimited peak would be 1.0 rad/s */
    check("cruise plan", traj_plan(&p, TRAJ_LI, 0.0, L, T, vmax, 0.0) == TRAJ_OK);
    check_close("cruise velocity", p.peak_vel_rad_s, vmax, 0.0);
    check_close("ramp", p.ramp_s, T - L / vmax, 1e-15);
    const double changes[2] = {p.ramp_s, T - p.ramp_s};
    for (int c = 0; c < 2; ++c) {
        const traj_sample lo = traj_eval(&p, changes[c] - 1e-13), at = traj_eval(&p, changes[c]);
        check_close("q continuous", lo.q_rad, at.q_rad, 1e-12);
        check_close("v continuous", lo.qd_rad_s, at.qd_rad_s, 1e-11);
        check_close("a continuous", lo.qdd_rad_s2, at.qdd_rad_s2, 1e-9);
        check_close("cruising", at.qd_rad_s, vmax, 1e-12);
    }
}

static void test_degenerate(void)
{
    traj_profile p;
    for (int k = 0; k < 4; ++k) {
        check("same point, zero time", traj_plan(&p, KINDS[k], 0.5, 0.5, 0.0, 0.0, 0.0) == TRAJ_OK);
        const traj_sample s = traj_eval(&p, 0.0);
        check("rest, no NaN", s.q_rad == 0.5 && s.qd_rad_s == 0.0 && s.qdd_rad_s2 == 0.0);
        check("same point, some time", traj_plan(&p, KINDS[k], 0.5, 0.5, 2.0, 1.0, 1.0) == TRAJ_OK);
        check("rest all along", traj_eval(&p, 1.0).q_rad == 0.5 && traj_eval(&p, 1.0).qd_rad_s == 0.0);
        check("jump", traj_plan(&p, KINDS[k], 0.0, 1.0, 0.0, 0.0, 0.0) == TRAJ_TOO_FAST);
        check("jump rests at q0", traj_eval(&p, 0.0).q_rad == 0.0 && traj_eval(&p, 9.0).q_rad == 0.0);
        check("NaN q", traj_plan(&p, KINDS[k], NAN, 1.0, 1.0, 0.0, 0.0) == TRAJ_BAD_ARGUMENT);
        check("NaN q rests at 0", traj_eval(&p, 0.5).q_rad == 0.0);
        check("negative T", traj_plan(&p, KINDS[k], 0.0, 1.0, -1.0, 0.0, 0.0) == TRAJ_BAD_ARGUMENT);
        check("infinite T", traj_plan(&p, KINDS[k], 0.0, 1.0, INFINITY, 0.0, 0.0) == TRAJ_BAD_ARGUMENT);
        check("NaN limit", traj_plan(&p, KINDS[k], 0.0, 1.0, 1.0, NAN, 0.0) == TRAJ_BAD_ARGUMENT);
        check("too fast", traj_plan(&p, KINDS[k], 0.0, 1.0, 1.0, 0.9, 0.0) == TRAJ_TOO_FAST);
        check("infinite limit is none", traj_plan(&p, KINDS[k], 0.0, 1.0, 1.0, INFINITY, INFINITY) == TRAJ_OK);
    }
    check("unknown kind", traj_plan(&p, (traj_kind)7, 0.0, 1.0, 1.0, 0.0, 0.0) == TRAJ_BAD_ARGUMENT);
}

/* At its minimum duration each profile plans and touches a limit; 1 % faster it cannot (except
 * Li and trapezoid with only a speed limit, which may then cruise: see traj_min_duration). */
static void test_min_duration(void)
{
    const double vmax = 1.5, amax[2] = {0.0, 4.0}, dists[3] = {0.2, 1.0, 6.0};
    for (int k = 0; k < 4; ++k) {
        for (int a = 0; a < 2; ++a) {
            for (int d = 0; d < 3; ++d) {
                traj_profile p;
                double T;
                check("min ok", traj_min_duration(KINDS[k], 1.0, 1.0 - dists[d], vmax, amax[a], &T) == TRAJ_OK);
                check("plans at the minimum",
                      traj_plan(&p, KINDS[k], 1.0, 1.0 - dists[d], T, vmax, amax[a]) == TRAJ_OK);
                /* peaks measured on the evaluated profile, not read from the plan */
                double v_peak = 0.0, a_peak = 0.0;
                for (int i = 0; i <= 4000; ++i) {
                    const traj_sample s = traj_eval(&p, T * i / 4000.0);
                    v_peak = fmax(v_peak, fabs(s.qd_rad_s));
                    a_peak = fmax(a_peak, fabs(s.qdd_rad_s2));
                }
                check("within the speed limit", v_peak <= vmax * (1 + 1e-9));
                check("within the acceleration limit", amax[a] == 0 || a_peak <= amax[a] * (1 + 1e-9));
                const int v_tight = v_peak > vmax * (1 - 1e-5);
                const int a_tight = amax[a] > 0 && a_peak > amax[a] * (1 - 1e-5);
                check("a limit is reached", v_tight || a_tight);
                const int may_cruise = (KINDS[k] == TRAJ_LI || KINDS[k] == TRAJ_TRAPEZOID) && amax[a] == 0;
                check("faster fails", may_cruise
                                          || traj_plan(&p, KINDS[k], 1.0, 1.0 - dists[d], 0.99 * T, vmax,
                                                       amax[a]) == TRAJ_TOO_FAST);
            }
        }
    }
    double T = -1.0;
    check("no limits", traj_min_duration(TRAJ_LI, 0.0, 1.0, 0.0, 0.0, &T) == TRAJ_OK && T == 0.0);
}

static void test_synchronized(void)
{
    traj_profile p[3];
    const double q0[3] = {0.0, 1.0, -0.5}, qf[3] = {0.5, -1.0, -0.5}, vmax[3] = {1.0, 1.0, 1.0};
    size_t bad = 99;
    check("sync ok", traj_plan_synchronized(p, 3, TRAJ_LI, q0, qf, 0.1, vmax, NULL, &bad) == TRAJ_OK);
    /* joint 2 moves 2 rad: the slowest, 2 * 2 / 1.0 = 4 s */
    for (int j = 0; j < 3; ++j) check_close("same duration", p[j].duration_s, 4.0, 1e-15);
    check_close("slowest at its limit", fabs(traj_eval(&p[1], 2.0).qd_rad_s), 1.0, 1e-12);
    check_close("joint 1 slower", traj_eval(&p[0], 2.0).qd_rad_s, 2 * 0.5 / 4.0, 1e-12);
    check_close("still joint stays", traj_eval(&p[2], 1.3).q_rad, -0.5, 0.0);
    check("longer asked, longer given",
          traj_plan_synchronized(p, 3, TRAJ_CUBIC, q0, qf, 9.0, vmax, NULL, &bad) == TRAJ_OK
              && p[0].duration_s == 9.0);
    /* joint 2 can cruise at its limit to make 2 rad in 3 s; in 1.5 s it cannot, so 4 s it is */
    check("feasible duration kept",
          traj_plan_synchronized(p, 3, TRAJ_LI, q0, qf, 3.0, vmax, NULL, &bad) == TRAJ_OK
              && p[2].duration_s == 3.0 && fabs(traj_eval(&p[1], 1.5).qd_rad_s) == 1.0);
    check("too short stretched",
          traj_plan_synchronized(p, 3, TRAJ_LI, q0, qf, 1.5, vmax, NULL, &bad) == TRAJ_OK
              && p[0].duration_s == 4.0);
    const double broken[3] = {0.0, NAN, 0.0};
    check("bad joint named", traj_plan_synchronized(p, 3, TRAJ_LI, q0, broken, 1.0, NULL, NULL, &bad)
                                     == TRAJ_BAD_ARGUMENT
                                 && bad == 1);
    check("no limits, no time",
          traj_plan_synchronized(p, 3, TRAJ_QUINTIC, q0, qf, 0.0, NULL, NULL, &bad) == TRAJ_TOO_FAST && bad == 0);
}

/* Two segments of a path meet continuously, and the batch form agrees with the single one. */
static void test_path(void)
{
    traj_profile seg[4];
    const double a[2] = {0.0, 0.0}, b[2] = {1.0, -0.5}, c[2] = {0.2, 0.5}, start[2] = {0.5, 2.5};
    traj_plan_synchronized(seg, 2, TRAJ_QUINTIC, a, b, 2.0, NULL, NULL, NULL);
    traj_plan_synchronized(seg + 2, 2, TRAJ_QUINTIC, b, c, 1.0, NULL, NULL, NULL);
    const double t[6] = {0.0, 0.5, 1.5, 2.5 - 1e-13, 2.5, 4.0};
    double q[12], qd[12];
    traj_path_eval_many(seg, start, 2, 2, t, 6, q, qd, NULL, NULL);
    for (int j = 0; j < 2; ++j) {
        check_close("before the first segment", q[j], a[j], 0.0);
        check_close("first segment starts", q[2 + j], a[j], 0.0);
        check_close("junction", q[6 + j], q[8 + j], 1e-12);
        check_close("junction is b", q[8 + j], b[j], 0.0);
        check_close("after the last", q[10 + j], c[j], 0.0);
        check_close("at rest at the end", qd[10 + j], 0.0, 0.0);
    }
    traj_sample s[2];
    traj_path_eval(seg, start, 2, 2, 1.5, s);
    check_close("single agrees", s[1].q_rad, q[5], 0.0);
    check_close("single agrees", s[1].q_rad, traj_eval(&seg[1], 1.0).q_rad, 0.0);
}

int main(void)
{
    test_boundary_conditions();
    test_li_peaks();
    test_derivatives();
    test_li_cruise_phase_changes();
    test_degenerate();
    test_min_duration();
    test_synchronized();
    test_path();
    return checks_report();
}
