"""Closed-form IK of the RRR, planar 3R and CRS arms: FK(IK(p)) = p in every quadrant, every
solution found and within limits, unreachable targets and singular cases reported."""

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from crslab import robots
from crslab.closed_ik import (
    OK,
    OUT_OF_LIMITS,
    SINGULAR_BASE,
    SINGULAR_CENTRE,
    UNREACHABLE,
    planar3r_ik,
    rrr_ik,
)

RRR = robots.load("rrr")
PLANAR = robots.load("planar3r")
CRS = robots.load("crs")


def rrr_fk(q, l1=10.0, l2=5.0, l3=5.0):
    """Seed 003's equations (1)-(3), written independently of the DH code."""
    reach = l1 + l2 * np.cos(q[..., 1]) + l3 * np.cos(q[..., 1] + q[..., 2])
    return np.stack([reach * np.cos(q[..., 0]), reach * np.sin(q[..., 0]),
                     l2 * np.sin(q[..., 1]) + l3 * np.sin(q[..., 1] + q[..., 2])], -1)


def planar_fk(q, a=(1.0, 1.0, 0.5)):
    """Seed 001's 3R formula: x, y of the tip and its heading."""
    c1, c12, c123 = q[..., 0], q[..., 0] + q[..., 1], q.sum(-1)
    x = a[0] * np.cos(c1) + a[1] * np.cos(c12) + a[2] * np.cos(c123)
    y = a[0] * np.sin(c1) + a[1] * np.sin(c12) + a[2] * np.sin(c123)
    return np.stack([x, y, c123], -1)


def same_angles(a, b, atol=1e-7):
    return np.all(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))) < atol, axis=-1)


def test_seed_003_point():
    """Seed 003's table: q = (0.15, 0.29, 0.57) rad gives (17.85, 2.698, 5.219)."""
    x, y, z = RRR.fk([0.15, 0.29, 0.57])[:3, 3]
    assert (round(x, 2), round(y, 3), round(z, 3)) == (17.85, 2.698, 5.219)  # as the seed prints them
    np.testing.assert_allclose(rrr_fk(np.array([0.15, 0.29, 0.57])), RRR.fk([0.15, 0.29, 0.57])[:3, 3],
                               atol=1e-12)
    sol = RRR.closed_ik(RRR.fk([0.15, 0.29, 0.57])[:3, 3])
    assert any(same_angles(q, [0.15, 0.29, 0.57]) for q in sol.q[sol.valid])


coord = st.floats(-21, 21, allow_nan=False)


@settings(max_examples=400, deadline=None)
@given(coord, coord, st.floats(-11, 11))
@example(0.0, 0.0, 1e-5)  # on the base axis, 5e-12 beyond full reach
@example(0.0, 0.0, 0.0)
def test_rrr_every_returned_solution_reaches_the_target_in_any_quadrant(x, y, z):
    sol = RRR.closed_ik([x, y, z])
    lo, hi = RRR.chain.lower, RRR.chain.upper
    for q, status in zip(sol.q, sol.status):
        assert np.all(np.isfinite(q))
        if status == OK:
            np.testing.assert_allclose(rrr_fk(q), [x, y, z], atol=1e-9)
            assert np.all((q >= lo) & (q <= hi))
        elif status == OUT_OF_LIMITS:
            np.testing.assert_allclose(rrr_fk(q), [x, y, z], atol=1e-9)
            assert not np.all((q >= lo) & (q <= hi))
    # unreachable exactly when no branch has the point within its annulus; within 1e-9 of the
    # boundary either answer is right (the OK slots were checked above to reach it to 1e-9)
    rho = np.hypot(x, y)
    dists = np.array([np.hypot(rho - 10, z), np.hypot(-rho - 10, z)])
    if np.any(np.abs(dists - 10) <= 1e-9):
        return
    reachable = bool(np.any(dists < 10))
    assert reachable == bool(np.any(sol.status != UNREACHABLE))


@settings(max_examples=400, deadline=None)
@given(st.floats(-np.pi, np.pi), st.floats(-np.pi / 2, np.pi / 2), st.floats(-np.pi, np.pi))
def test_rrr_finds_the_configuration_it_came_from(q1, q2, q3):
    """All solutions: the in-limit configuration that made the point is among the OK slots."""
    p = rrr_fk(np.array([q1, q2, q3]))
    assume(np.hypot(p[0], p[1]) > 1e-6)  # off the base axis, where q1 is free
    sol = RRR.closed_ik(p)
    assume(sol.singular == 0)  # at the shoulder centre q2 is free (test_rrr_singular_cases)
    assert np.any(same_angles(sol.q[sol.valid], [q1, q2, q3], atol=1e-6))


def test_rrr_counts_solutions_per_quadrant():
    # a point in each quadrant with two front solutions inside limits, back out of reach
    for heading in np.radians([30, 120, -150, -60, 90, 180, 0]):
        p = rrr_fk(np.array([heading, 0.2, 0.9]))
        sol = RRR.closed_ik(p)
        assert sol.status.tolist() == [OK, OK, UNREACHABLE, UNREACHABLE], heading
        np.testing.assert_allclose(rrr_fk(sol.q[:2]), [p, p], atol=1e-9)


def test_rrr_back_branch_and_limits_on_a_short_first_link():
    # with a short first link the arm can also reach back over the base: four exact solutions,
    # and exactly those with |q2| > pi/2 are flagged as outside seed 003's limits
    lim = np.array([np.pi, np.pi / 2, np.pi])
    sol = rrr_ik((0.0, 1.0, 5.0, 5.0), [2.0, 0.0, 1.0], -lim, lim)
    np.testing.assert_allclose(rrr_fk(sol.q, 1.0, 5.0, 5.0), np.tile([2.0, 0.0, 1.0], (4, 1)), atol=1e-9)
    expected = np.where(np.abs(sol.q[:, 1]) <= np.pi / 2, OK, OUT_OF_LIMITS)
    assert sol.status.tolist() == expected.tolist()
    assert OK in expected and OUT_OF_LIMITS in expected
    np.testing.assert_allclose(sol.q[2:, 0], np.pi)  # the back branch faces away from the target


def test_rrr_singular_cases():
    on_axis = rrr_ik((0.0, 10.0, 5.0, 5.0), [0.0, 0.0, 3.0])
    assert on_axis.singular & SINGULAR_BASE
    shoulder = rrr_ik((0.0, 10.0, 5.0, 5.0), [10.0, 0.0, 0.0])   # at joint 2's axis, a2 = a3
    assert shoulder.singular & SINGULAR_CENTRE
    np.testing.assert_allclose(shoulder.q[0], [0.0, 0.0, np.pi], atol=1e-12)
    np.testing.assert_allclose(rrr_fk(shoulder.q[0]), [10.0, 0.0, 0.0], atol=1e-9)
    # seed 003's formulas divide by cos(q1): x = 0 is an ordinary target here
    sol = RRR.closed_ik([0.0, 15.0, 2.0])
    assert np.sum(sol.valid) == 2
    np.testing.assert_allclose(rrr_fk(sol.q[sol.valid]), [[0, 15, 2], [0, 15, 2]], atol=1e-9)


@settings(max_examples=400, deadline=None)
@given(st.floats(-np.pi, np.pi), st.floats(-np.pi, np.pi), st.floats(-np.pi, np.pi))
def test_planar3r_both_elbows_round_trip(q1, q2, q3):
    target = planar_fk(np.array([q1, q2, q3]))
    sol = PLANAR.closed_ik(target)
    assert sol.status.tolist() == [OK, OK]
    got = planar_fk(sol.q)
    np.testing.assert_allclose(got[:, :2], [target[:2]] * 2, atol=1e-9)
    assert np.all(same_angles(got[:, 2:], target[2:], atol=1e-9))
    assert np.sin(sol.q[0, 1]) >= -1e-12 and np.sin(sol.q[1, 1]) <= 1e-12  # q2 = +-pi is both
    if sol.singular == 0:  # with the wrist on joint 1 (a1 = a2), q1 is free
        assert np.any(same_angles(sol.q, [q1, q2, q3], atol=1e-6))


def test_planar3r_unreachable_singular_and_limits():
    far = planar3r_ik((1.0, 1.0, 0.5), [3.0, 0.0, 0.0])
    assert far.status.tolist() == [UNREACHABLE, UNREACHABLE] and np.all(np.isfinite(far.q))
    centre = planar3r_ik((1.0, 1.0, 0.5), [0.5, 0.0, 0.0])    # wrist point on joint 1
    assert centre.singular & SINGULAR_CENTRE and centre.status.tolist() == [OK, OK]
    np.testing.assert_allclose(planar_fk(centre.q)[:, :2], [[0.5, 0], [0.5, 0]], atol=1e-9)
    limited = planar3r_ik((1.0, 1.0, 0.5), planar_fk(np.array([0.3, 0.8, -0.2])), lower=[-np.pi, 0, -np.pi],
                          upper=[np.pi, np.pi, np.pi])
    assert limited.status.tolist() == [OK, OUT_OF_LIMITS]


def test_planar3r_link_lengths_are_parameters():
    short = robots.load("planar3r", {"a1": 0.4, "a3": 0.2})
    np.testing.assert_allclose(short.chain.a, [0.4, 1.0, 0.2])
    q = np.array([0.2, -1.1, 0.6])
    target = planar_fk(q, (0.4, 1.0, 0.2))
    sol = short.closed_ik(target)
    assert np.any(same_angles(sol.q[sol.valid], q, atol=1e-9))


@settings(max_examples=300, deadline=None)
@given(coord, coord, st.floats(-10, 30))
def test_crs_robot_closed_form_round_trip(x, y, z):
    sol = CRS.closed_ik([x, y, z])
    reachable = np.hypot(np.hypot(x, y), z - 10) <= 20
    for q, status in zip(sol.q, sol.status):
        if status == OK:  # crslab.crs puts targets within 1e-9 in of the base axis on it
            np.testing.assert_allclose(CRS.fk(q)[:3, 3], [x, y, z], atol=2e-9)
    if reachable and np.hypot(np.hypot(x, y), z - 10) < 20 - 1e-9:
        assert sol.status.tolist() == [OK, OK]
    if not reachable:
        assert sol.status.tolist() == [UNREACHABLE, UNREACHABLE]


def test_batches_keep_their_shape():
    targets = np.random.default_rng(0).uniform(-15, 15, size=(4, 6, 3))
    sol = RRR.closed_ik(targets)
    assert sol.q.shape == (4, 6, 4, 3) and sol.status.shape == (4, 6, 4) and sol.singular.shape == (4, 6)
    with pytest.raises(ValueError, match="a2 > 0"):
        rrr_ik((0, 1, 0, 1), [1, 1, 1])
