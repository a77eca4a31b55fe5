"""The trajectory profiles (crslab.traj.profiles over csrc/kin/traj_profiles.c), checked against
numpy re-implementations written here from the formulas, and against their own invariants."""

import math
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from crslab.traj.profiles import PROFILES, TrajectoryError, min_duration, plan_move, plan_path

# ---- reference implementations, written independently of the C core ----

def li_reference(t, L, T, vmax=None):
    """Seed 003's formulas (7) and (8), with its T2 read as the length of the cruise phase.

    A = 8L/T^2 and T1 = sqrt(2L/A) (= T/2) without a cruise; with a speed limit V below 2L/T the
    ramps last T1 = T - L/V, A = 2V/T1, and the cruise T2 = T - 2 T1."""
    A = 8 * L / T**2
    T1 = math.sqrt(2 * L / A)
    T2 = 0.0
    if vmax is not None and 2 * abs(L) / T > vmax:
        V = math.copysign(vmax, L)
        T1 = T - L / V
        A = 2 * V / T1
        T2 = T - 2 * T1
    m, n = 2 * math.pi / T1, T1 / (2 * math.pi)
    t = np.clip(t, 0, T)
    acc = A / 2 * n**2 * (0.5 * (m * t) ** 2 - (1 - np.cos(m * t)))
    cruise = 0.25 * A * T1**2 + 0.5 * A * T1 * (t - T1)
    tau = t - T1 - T2
    dec = (0.25 * A * T1**2 + 0.5 * A * T1 * T2
           + A / 2 * n**2 * ((2 * math.pi) ** 2 * tau / T1 - 0.5 * (m * tau) ** 2 + (1 - np.cos(m * tau))))
    return np.where(t <= T1, acc, np.where(t <= T1 + T2, cruise, dec))


def poly_reference(kind, t, L, T):
    """q/L as a polynomial in s = t/T, highest power first (numpy.polyval order)."""
    coeffs = {"cubic": [-2, 3, 0, 0], "quintic": [6, -15, 10, 0, 0, 0]}[kind]
    return L * np.polyval(coeffs, np.clip(t, 0, T) / T)


def trapezoid_reference(t, L, T, vmax=None):
    V = 1.5 * L / T
    if vmax is not None and abs(V) > vmax:
        V = math.copysign(vmax, L)
    Ta = T - L / V
    a = V / Ta
    t = np.clip(t, 0, T)
    return np.where(t < Ta, 0.5 * a * t**2,
                    np.where(t <= T - Ta, 0.5 * a * Ta**2 + V * (t - Ta), L - 0.5 * a * (T - t) ** 2))


def reference(kind, t, L, T, vmax=None):
    if kind == "li":
        return li_reference(t, L, T, vmax)
    if kind == "trapezoid":
        return trapezoid_reference(t, L, T, vmax)
    return poly_reference(kind, t, L, T)


def one_joint(kind, q0, qf, T, vmax=None):
    return plan_move(kind, [q0], [qf], duration_s=T, vmax=vmax)


# ---- the profiles against the references ----

@pytest.mark.parametrize("kind", list(PROFILES))
@pytest.mark.parametrize("q0, qf, T", [(0.0, 1.0, 2.0), (0.7, -1.9, 0.8), (-2.0, -1.5, 5.0)])
def test_position_matches_the_formula(kind, q0, qf, T):
    t = np.linspace(-0.5, T + 0.5, 3001)
    got = one_joint(kind, q0, qf, T).evaluate(t).q[:, 0]
    np.testing.assert_allclose(got, q0 + reference(kind, t, qf - q0, T), rtol=0, atol=1e-12)


@pytest.mark.parametrize("kind", ["li", "trapezoid"])
def test_cruise_under_a_speed_limit_matches_the_formula(kind):
    L, T, vmax = -1.2, 1.5, 1.0  # unlimited peaks 1.6 (li) and 1.2 (trapezoid) rad/s
    t = np.linspace(0, T, 3001)
    s = one_joint(kind, 0.3, 0.3 + L, T, vmax=vmax).evaluate(t)
    np.testing.assert_allclose(s.q[:, 0], 0.3 + reference(kind, t, L, T, vmax), rtol=0, atol=1e-12)
    assert np.abs(s.qd).max() == pytest.approx(vmax, rel=1e-12)
    cruising = np.isclose(np.abs(s.qd[:, 0]), vmax, rtol=1e-12, atol=0)
    assert cruising.mean() > 0.2  # a real cruise phase, not one sample at the peak


# ---- boundary conditions and peaks ----

@pytest.mark.parametrize("kind", list(PROFILES))
def test_each_profile_starts_and_ends_at_rest(kind):
    q0, qf, T = 0.25, -0.75, 1.6
    s = one_joint(kind, q0, qf, T).evaluate([0.0, T])
    assert s.q[:, 0].tolist() == [q0, qf]
    np.testing.assert_allclose(s.qd[:, 0], 0.0, atol=1e-15)
    L = qf - q0
    if kind in ("li", "quintic"):  # their accelerations also start and end at zero
        np.testing.assert_allclose(s.qdd[:, 0], 0.0, atol=1e-14)
    elif kind == "cubic":  # the cubic's acceleration jumps to +-6L/T^2 at the ends
        np.testing.assert_allclose(s.qdd[:, 0], [6 * L / T**2, -6 * L / T**2], rtol=1e-12)
    if kind == "li":
        np.testing.assert_allclose(s.jerk[:, 0], 0.0, atol=1e-13)


def test_li_peaks_without_cruise_are_2L_over_T_and_8L_over_T_squared():
    L, T = 1.3, 2.6
    t = np.linspace(0, T, 20001)  # includes T/4 and T/2 exactly
    s = one_joint("li", 0.0, L, T).evaluate(t)
    assert s.qd.max() == pytest.approx(2 * L / T, rel=1e-12)
    assert s.qdd.max() == pytest.approx(8 * L / T**2, rel=1e-12)
    assert s.qdd.min() == pytest.approx(-8 * L / T**2, rel=1e-12)
    assert t[s.qd.argmax()] == pytest.approx(T / 2)
    assert t[s.qdd.argmax()] == pytest.approx(T / 4)


@pytest.mark.parametrize("kind, peak_v, peak_a", [
    ("quintic", 15 / 8, 10 / math.sqrt(3)), ("cubic", 1.5, 6.0), ("trapezoid", 1.5, 4.5)])
def test_closed_form_peaks(kind, peak_v, peak_a):
    L, T = 0.9, 1.2
    t = np.linspace(0, T, 60001)
    s = one_joint(kind, 0.0, L, T).evaluate(t)
    assert np.abs(s.qd).max() == pytest.approx(peak_v * L / T, rel=1e-8)
    assert np.abs(s.qdd).max() == pytest.approx(peak_a * L / T**2, rel=1e-6)


# ---- continuity and derivatives ----

def test_li_position_is_continuous_at_every_phase_change():
    T, L, vmax = 2.0, 1.0, 0.7
    move = one_joint("li", 0.0, L, T, vmax=vmax)
    ramp = T - L / vmax
    for change in (ramp, T / 2, T - ramp):
        s = move.evaluate([np.nextafter(change, -1), change, np.nextafter(change, 3)])
        assert np.ptp(s.q) <= 1e-12
        assert np.ptp(s.qd) <= 1e-12
        assert np.ptp(s.qdd) <= 1e-9


@pytest.mark.parametrize("kind", list(PROFILES))
@pytest.mark.parametrize("vmax", [None, 0.8])
def test_each_derivative_is_the_finite_difference_of_the_one_before(kind, vmax):
    T, L, h = 1.4, 1.0, 1e-6
    move = one_joint(kind, 0.2, 0.2 + L, T, vmax=vmax if kind in ("li", "trapezoid") else None)
    t = np.linspace(0.01, T - 0.01, 397)
    if kind == "trapezoid":  # the acceleration jumps at the ends of the ramps
        ramp = move.c_segments[0].ramp_s
        t = t[(np.abs(t - ramp) > 1e-3) & (np.abs(t - (T - ramp)) > 1e-3)]
    lo, mid, hi = move.evaluate(t - h), move.evaluate(t), move.evaluate(t + h)
    np.testing.assert_allclose((hi.q - lo.q) / (2 * h), mid.qd, atol=1e-7)
    np.testing.assert_allclose((hi.qd - lo.qd) / (2 * h), mid.qdd, atol=1e-6)
    np.testing.assert_allclose((hi.qdd - lo.qdd) / (2 * h), mid.jerk, atol=1e-4)


# ---- synchronization and limits ----

def test_joints_are_synchronized_to_the_slowest():
    q0, qf = [0.0, 0.0, 1.0], [0.5, -2.0, 1.0]
    move = plan_move("li", q0, qf, vmax=[1.0, 2.0, 1.0])
    # joint 1 needs 2 * 0.5 / 1.0 = 1 s, joint 2 needs 2 * 2 / 2 = 2 s, joint 3 does not move
    assert move.duration_s.tolist() == [2.0]
    t = np.linspace(0, 2, 2001)
    s = move.evaluate(t)
    np.testing.assert_allclose(s.q[-1], qf, atol=0)
    np.testing.assert_allclose(s.q[:, 0], li_reference(t, 0.5, 2.0), atol=1e-12)
    assert np.abs(s.qd[:, 1]).max() == pytest.approx(2.0, rel=1e-12)  # the slowest at its limit
    assert np.abs(s.qd[:, 0]).max() == pytest.approx(0.5, rel=1e-12)
    assert np.all(s.q[:, 2] == 1.0) and np.all(s.qd[:, 2] == 0.0)


@pytest.mark.parametrize("kind", list(PROFILES))
def test_the_minimum_duration_meets_both_limits_and_touches_one(kind):
    vmax, amax = 1.2, 3.0
    for L in (0.1, 0.9, 5.0):  # short moves are acceleration bound, long ones speed bound
        T = min_duration(kind, 0.0, L, vmax, amax)[0]
        t = np.linspace(0, T, 40001)
        s = plan_move(kind, [0.0], [L], duration_s=T, vmax=vmax, amax=amax).evaluate(t)
        v, a = np.abs(s.qd).max(), np.abs(s.qdd).max()
        assert v <= vmax * (1 + 1e-9) and a <= amax * (1 + 1e-9)
        assert v > vmax * (1 - 1e-6) or a > amax * (1 - 1e-6)
        with pytest.raises(TrajectoryError, match="too fast"):
            plan_move(kind, [0.0], [L], duration_s=0.99 * T, vmax=vmax, amax=amax)


def test_li_minimum_duration_with_a_cruise_is_L_over_v_plus_2v_over_a():
    # long move: ramps of 2 vmax/amax at amax each end, cruise between
    assert min_duration("li", 0.0, 4.0, 1.0, 2.0)[0] == pytest.approx(4.0 / 1.0 + 2 * 1.0 / 2.0)


def test_a_segment_with_a_given_time_that_is_too_short_names_segment_and_joint():
    # quintic peak velocity 15L/(8T): 2 rad at 2 rad/s needs 1.875 s
    with pytest.raises(TrajectoryError, match=r"segment 2: .* joint 2 .* at least 1.875 s") as info:
        plan_path("quintic", [[0, 0], [0.1, 0.1], [0.2, 2.1]], durations_s=[1.0, 1.5], vmax=2.0)
    assert (info.value.segment, info.value.joint) == (1, 1)


def test_li_keeps_a_given_time_by_cruising_and_names_the_bound_when_it_cannot():
    path = plan_path("li", [[0.0], [2.0]], durations_s=[1.5], vmax=2.0)  # 2L/T = 2.67 > 2: cruise
    assert path.duration_s.tolist() == [1.5]
    assert path.evaluate([0.75]).qd[0, 0] == pytest.approx(2.0, rel=1e-12)
    with pytest.raises(TrajectoryError, match=r"needs more than 1 s within 2 rad/s"):
        plan_path("li", [[0.0], [2.0]], durations_s=[1.0], vmax=2.0)


def test_path_segments_follow_each_other_and_join_at_rest():
    q = [[0.0, 0.0], [1.0, -1.0], [1.0, 0.5], [0.0, 0.0]]
    path = plan_path("quintic", q, durations_s=[1.0, np.nan, 2.0], vmax=1.875)
    assert path.duration_s.tolist() == [1.0, 1.5, 2.0]  # the middle one: 1.875 * 1.5 / 1.875
    assert path.start_s.tolist() == [0.0, 1.0, 2.5]
    s = path.evaluate(np.concatenate([path.start_s, [path.end_s]]))
    np.testing.assert_allclose(s.q, q, atol=0)
    np.testing.assert_allclose(s.qd, 0.0, atol=1e-15)


def test_sampling_uses_integer_ticks():
    path = plan_path("cubic", [[0.0], [1.0], [0.0]], durations_s=[0.3, 0.4])
    t, s = path.sample(1000)
    assert t.size == 701 and t[-1] == 0.7
    np.testing.assert_array_equal(t, np.arange(701) / 1000)
    assert s.q.shape == (701, 1)


# ---- degenerate cases ----

@pytest.mark.parametrize("kind", list(PROFILES))
def test_no_motion_and_no_time_give_a_rest_not_nan(kind):
    for T in (0.0, 1.0, None):
        move = plan_move(kind, [0.4, -1.0], [0.4, -1.0], duration_s=T)
        s = move.evaluate(np.linspace(-1, 2, 31))
        assert np.all(s.q == [0.4, -1.0])
        assert not np.any(s.qd) and not np.any(s.qdd) and not np.any(s.jerk)


@pytest.mark.parametrize("kind", list(PROFILES))
def test_a_jump_in_no_time_is_refused(kind):
    with pytest.raises(TrajectoryError, match="cannot move from 0 to 1 in 0 s"):
        plan_move(kind, [0.0], [1.0], duration_s=0.0)
    with pytest.raises(TrajectoryError, match="give a duration or a speed limit"):
        plan_move(kind, [0.0], [1.0])


def test_bad_inputs_are_refused():
    with pytest.raises(ValueError, match="unknown profile"):
        plan_move("sine", [0.0], [1.0], 1.0)
    with pytest.raises(TrajectoryError, match="joint 1 from nan"):
        plan_move("li", [np.nan], [1.0], 1.0)
    with pytest.raises(TrajectoryError, match="duration -1"):
        plan_move("li", [0.0], [1.0], -1.0)


# ---- invariants over random moves ----

@settings(max_examples=150, deadline=None)
@given(kind=st.sampled_from(list(PROFILES)),
       q0=st.floats(-4, 4), L=st.floats(-6, 6).filter(lambda x: abs(x) > 1e-6),
       T=st.floats(0.01, 20), cap=st.none() | st.floats(0.7, 0.99))
def test_random_moves_meet_the_references_and_their_limits(kind, q0, L, T, cap):
    vmax = None
    if cap is not None:
        vmax = cap * {"li": 2.0, "trapezoid": 1.5, "cubic": 1.5, "quintic": 1.875}[kind] * abs(L) / T
        if kind in ("cubic", "quintic"):  # no cruise to fall back on: a lower cap is too fast
            with pytest.raises(TrajectoryError):
                one_joint(kind, q0, q0 + L, T, vmax)
            return
    t = np.linspace(0, T, 801)
    s = one_joint(kind, q0, q0 + L, T, vmax).evaluate(t)
    scale = max(1.0, abs(q0) + abs(L))
    np.testing.assert_allclose(s.q[:, 0], q0 + reference(kind, t, L, T, vmax), atol=1e-12 * scale)
    assert s.q[0, 0] == q0 and s.q[-1, 0] == q0 + L  # the end points exactly
    steps = np.diff(s.q[:, 0]) * np.sign(L)
    assert steps.min() >= -1e-12 * scale  # every profile moves one way only
    if vmax is not None:
        assert np.abs(s.qd).max() <= vmax * (1 + 1e-9)


# ---- a lab file can use the profiles ----

LAB_USING_PROFILES = r"""
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"
#include "traj_profiles.h"

float offset_Enc2_rad = -0.37;
float offset_Enc3_rad = 0.27;
long mycount = 0;
static traj_profile move[3];
float qdes1 = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2, float *tau3,
         int error)
{
    const double q0[3] = {theta1motor, theta2motor, theta3motor}, qf[3] = {0.5, 0.3, 0.2};
    if (mycount == 0) traj_plan_synchronized(move, 3, TRAJ_LI, q0, qf, 2.0, NULL, NULL, NULL);
    traj_sample d = traj_eval(&move[0], mycount * 0.001);
    qdes1 = d.q_rad;
    *tau1 = 0; *tau2 = 0; *tau3 = 0;
    (void)error;
    mycount++;
}

void printing(void) { serial_printf(&SerialA, "%.3f\n\r", qdes1); }
"""


def test_a_gen_a_lab_file_can_include_the_profiles_header(tmp_path):
    """What the tracking lab will do: include traj_profiles.h beside the framework's headers
    (compiled here for syntax and types only, as C11 with every warning an error)."""
    root = Path(__file__).resolve().parents[1]
    src = tmp_path / "lab_traj.c"
    src.write_text(LAB_USING_PROFILES)
    r = subprocess.run(["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-fsyntax-only",
                        "-I", str(root / "csrc" / "firmware" / "include"), "-I", str(root / "csrc" / "kin"),
                        str(src)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
