"""The framework's hold controller on the simulated arm, as the real one (docs/framework.md section 4):
references from 0, following the arm inside the envelope, re-anchored outside when more than
0.15 rad away; Kp 15/25 by the 0.1 rad error; Kd 1 on the recursively averaged velocity, with
joint 2's quirk. Checked tick for tick against a second implementation written here in numpy
float32 (with the C28x FPU's one difference from IEEE float that the hold meets: a result below
the smallest normal float is zero)."""

from pathlib import Path

import numpy as np
import pytest

from crslab import crs
from crslab.framework_facts import CLAMP_UNITS, STARTUP_TICKS
from crslab.run.api import simulate

LABS = Path(__file__).parent / "labs"
F = np.float32
EDGE_RAD = 0.6667 * np.pi  # |th1| beyond this is outside the envelope


def reference_hold(enc_rad: np.ndarray, outside: np.ndarray, startup: int) -> np.ndarray:
    """The hold controller's output at every tick, from the angles the framework read."""
    ref = np.zeros(3, F)
    prev = np.zeros(3, F)
    old1 = np.zeros(3, F)
    old2 = np.zeros(3, F)
    out = np.zeros(enc_rad.shape, F)
    for k, angles in enumerate(enc_rad.astype(F)):
        e = ref - angles
        raw = (angles - prev) / F(0.001)
        v = np.array([(raw[0] + old1[0] + old2[0]) / F(3),
                      (raw[1] + old2[1] + old2[1]) / F(3),   # joint 2: the older average twice
                      (raw[2] + old1[2] + old2[2]) / F(3)], F)
        v[np.abs(v) < np.finfo(F).tiny] = 0  # the F28335's FPU keeps no subnormal: zero
        old2, old1, prev = old1, v, angles
        kp = np.where(np.abs(e) > F(0.1), F(15), F(25))
        out[k] = kp * e - v
        if k >= startup:
            ref = np.where(np.abs(ref - angles) > F(0.15), angles, ref) if outside[k] else angles
    return out


def check_hold_tick_for_tick(run, startup: int = STARTUP_TICKS) -> int:
    log = run.log
    enc = log["enc_rad"]
    outside = crs.outside_envelope(enc).astype(bool)
    np.testing.assert_array_equal(outside[startup:], log["safety"][startup:, 0] == 1)
    hold = np.clip(reference_hold(enc, outside, startup), -CLAMP_UNITS, CLAMP_UNITS)
    used = outside & (np.arange(len(enc)) >= startup)
    np.testing.assert_array_equal(log["tau_applied"][used], hold[used].astype(np.float64))
    return int(used.sum())


@pytest.fixture(scope="module")
def full_torque():
    return simulate(LABS / "open_loop_tau1_full.c", "hands_off", duration_s=8.0, log=True)


def test_full_open_loop_torque_leaves_joint_1_past_the_envelope_with_error_1(full_torque):
    log = full_torque.log
    th1 = log["enc_rad"][:, 0]
    # *tau1 = 5 swings joint 1 out (at the drive's top speed, about 3.7 rad/s); the hold
    # controller's reference re-anchors where the arm went, and holds it just past the edge
    # (2.09 rad): the lab's torques are discarded from the first tick outside
    assert EDGE_RAD < th1[-1] < EDGE_RAD + 0.1
    assert np.abs(np.diff(log["enc_rad"][:, 0])).max() < 0.0045  # never faster than 4.5 rad/s
    assert np.all(log["safety"][-2000:, 0] == 1)
    # the lab hears error 1 (it plots the error it receives) and it never goes back to 0
    lines = full_torque.lines()
    assert len(lines) == 1 and lines[0].startswith("error 1 at ")
    # it printed the first angle outside the envelope: a few ms of travel past the edge
    assert EDGE_RAD < float(lines[0].split()[3]) < EDGE_RAD + 0.02
    assert np.all(log["plot"][-2000:, 3] == 1.0)
    # held where it is: once still, the pull is a fraction of a unit, not 5
    assert np.all(np.abs(log["tau_applied"][-1000:, 0]) < 1.0)


def test_the_hold_output_is_the_real_controllers_tick_for_tick(full_torque):
    assert check_hold_tick_for_tick(full_torque) > 3000


def test_on_the_tour_the_hand_pushes_the_arm_out_and_the_hold_follows_tick_for_tick():
    tour = simulate(log=True)
    used = check_hold_tick_for_tick(tour)
    assert used > 2000  # DH zero and straight up are outside the envelope


def test_references_start_at_0_so_the_first_ticks_see_the_offsets_as_a_jump():
    # before the startup gate the output is not used, but the controller runs from tick 0: with
    # references 0, tick 0 sees joint 2 at -0.42 rad (e = 0.42, Kp 15) moving -420 rad/s in one
    # ms, averaged to -140 (joint 2 counts the older average twice): u2 = 6.3 + 140
    enc = np.array([[0.0, -0.42, 0.24]] * 3)
    out = reference_hold(enc, np.zeros(3, bool), STARTUP_TICKS)
    np.testing.assert_allclose(out[0], [0.0, 146.3, -83.6], rtol=1e-6)
    np.testing.assert_allclose(out[1, 1], 15 * 0.42 - (0 + 0 + 0) / 3, rtol=1e-6)  # v2 = (0 + 2*0)/3
    np.testing.assert_allclose(out[2, 1], 15 * 0.42 - (0 - 140 - 140) / 3, rtol=1e-6)
