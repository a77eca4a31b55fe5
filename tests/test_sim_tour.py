"""The default run: Lab 1 on the tour prints what a real board prints at each pose."""

import numpy as np
import pytest

from crslab import crs
from crslab.run.api import simulate


@pytest.fixture(scope="module")
def tour():
    return simulate(log=True)


NO_SOLUTION = b"IK: no solution\n\r"


def printed_blocks(run):
    """(tick, motor_deg, xyz_in, ik_motor_deg) for every three-line print; ik_motor_deg None where
    the lab printed that its IK has no solution."""
    out = []
    calls = run.calls
    for i in range(0, len(calls) - 2, 3):
        rows = [np.array([float(v) for v in calls[i + k][1].split()]) for k in range(2)]
        third = calls[i + 2][1]
        ik = None if third == NO_SOLUTION else np.array([float(v) for v in third.split()])
        out.append((calls[i][0], *rows, ik))
    return out


def block_at(run, t_s):
    return min(printed_blocks(run), key=lambda b: abs(b[0] - t_s * 1000))


def test_prints_every_half_second_three_lines(tour):
    ticks = [t for t, _ in tour.calls]
    assert ticks[0] == 4100
    assert sorted(set(np.diff(sorted(set(ticks))))) == [500]
    assert len(tour.calls) == 3 * len(set(ticks))
    assert all(d.endswith(b"\n\r") for _, d in tour.calls)


def test_motor_zero_prints_10_0_20(tour):
    _, motor, xyz, ik = block_at(tour, 9.0)  # held at motor zero from 7 s to 9.5 s
    np.testing.assert_allclose(xyz, [10, 0, 20], atol=0.05)
    np.testing.assert_allclose(motor, [0, 0, 0], atol=0.2)
    np.testing.assert_allclose(ik, motor, atol=0.02)


def test_dh_zero_prints_about_20_0_10_against_the_hold_controller(tour):
    _, motor, xyz, _ = block_at(tour, 13.5)
    np.testing.assert_allclose(xyz, [20, 0, 10], atol=0.3)
    log = tour.log
    i = int(np.searchsorted(log["tick"][:, 0], 13500))
    assert log["safety"][i, 0] == 1  # outside the envelope: the framework's hold controller acts
    # ... toward references re-anchored where the hand took the arm: a pull of at most about
    # Kp 15 x 0.15 rad, not back to the envelope's edge (tests/test_sim_hold.py: tick for tick)
    assert np.all(np.abs(log["tau_applied"][i]) < 15 * 0.15 + 0.1)


def test_printed_numbers_are_fk_of_the_simulated_pose(tour):
    log = tour.log
    for tick, motor, xyz, _ik in printed_blocks(tour):
        i = int(np.searchsorted(log["tick"][:, 0], tick))
        true_motor = crs.dh_to_motor(log["qpos_dh_rad"][i])
        read = log["enc_rad"][i]  # the lab's offsets are the arm's resting pose: it reads true angles
        np.testing.assert_allclose(read, true_motor, atol=np.pi / 144000)  # to an encoder count
        # Gen A's printf truncates to the last digit shown
        np.testing.assert_allclose(motor, np.degrees(read), atol=0.01 + 1e-4)
        np.testing.assert_allclose(xyz, crs.fk(true_motor), atol=0.01)


def test_straight_up_prints_0_0_30(tour):
    _, motor, xyz, ik = block_at(tour, 18.0)
    np.testing.assert_allclose(xyz, [0, 0, 30], atol=0.05)
    # straight up is on the base axis, where every joint-1 angle is a solution: the lab's float
    # angles leave x a hair below zero and its IK may answer 180 deg; it must still land there
    np.testing.assert_allclose(crs.fk(np.radians(ik)), xyz, atol=0.02)


def test_the_elbow_straight_at_full_reach_is_a_hair_outside_it_in_the_board_s_float(tour):
    # on the way up the hand holds the elbow straight (motor 3 - motor 2 = -90 deg) and tilts the
    # shoulder: the tip is at full reach, where the law of cosines gives cos = 1 exactly; in the
    # board's 32-bit double the lab's FK and IK round it a hair past 1, and its IK says so
    _, motor, xyz, ik = block_at(tour, 15.6)
    assert motor[2] - motor[1] == pytest.approx(-90.0, abs=0.011)
    assert np.hypot(xyz[0], xyz[2] - 10.0) == pytest.approx(20.0, abs=0.02)  # upper arm + forearm, in
    assert ik is None
    # every other block of the tour has a solution, and it lands where the lab's FK put the tip
    solved = [b for b in printed_blocks(tour) if b[3] is not None]
    assert len(solved) == len(printed_blocks(tour)) - 1
    for _, _, xyz_b, ik_b in solved:
        np.testing.assert_allclose(crs.fk(np.radians(ik_b)), xyz_b, atol=0.02)


def test_back_at_rest_after_release(tour):
    _, motor, xyz, _ = printed_blocks(tour)[-1]
    np.testing.assert_allclose(motor, np.degrees([0, -0.42, 0.24]), atol=0.05)
