"""Rotations (crslab.rotation): round trips, the singular cases, and the rejection of non-rotations."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from crslab.rotation import (
    EULER_SINGULAR_COS,
    RotationError,
    axis_angle_to_matrix,
    check_rotation,
    euler_zyx_to_matrix,
    matrix_to_axis_angle,
    matrix_to_euler_zyx,
)


def rz(t):
    return np.array([[np.cos(t), -np.sin(t), 0], [np.sin(t), np.cos(t), 0], [0, 0, 1]])


def ry(t):
    return np.array([[np.cos(t), 0, np.sin(t)], [0, 1, 0], [-np.sin(t), 0, np.cos(t)]])


def rx(t):
    return np.array([[1, 0, 0], [0, np.cos(t), -np.sin(t)], [0, np.sin(t), np.cos(t)]])


def rodrigues(n, t):
    """Independent axis-angle: exp of the skew matrix through numpy's matrix power series."""
    k = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]]) * t
    out, term = np.eye(3), np.eye(3)
    for i in range(1, 40):
        term = term @ k / i
        out = out + term
    return out


angle = st.floats(-np.pi, np.pi, allow_nan=False)


@settings(max_examples=300, deadline=None)
@given(angle, st.floats(-np.pi / 2, np.pi / 2), angle)
def test_euler_zyx_is_rz_ry_rx_and_round_trips(a, b, g):
    r = euler_zyx_to_matrix([a, b, g])
    np.testing.assert_allclose(r, rz(a) @ ry(b) @ rx(g), atol=1e-14)
    back = matrix_to_euler_zyx(r)
    np.testing.assert_allclose(euler_zyx_to_matrix(back), r, atol=1e-12)
    if np.cos(b) > 1e-6:  # away from gimbal lock the angles themselves come back
        np.testing.assert_allclose(back, [a, b, g], atol=1e-8)


@pytest.mark.parametrize("beta", [np.pi / 2, -np.pi / 2])
@pytest.mark.parametrize("alpha, gamma", [(0.3, 0.1), (-2.0, 1.2), (3.0, -3.0)])
def test_gimbal_lock_sets_alpha_zero_and_keeps_the_matrix(alpha, beta, gamma):
    r = euler_zyx_to_matrix([alpha, beta, gamma])
    zyx, singular = matrix_to_euler_zyx(r, return_singular=True)
    assert singular
    assert zyx[0] == 0.0 and abs(zyx[1] - beta) < 1e-12
    # at beta = +pi/2 only alpha - gamma matters, at -pi/2 only alpha + gamma
    combined = alpha - gamma if beta > 0 else alpha + gamma
    assert np.isclose(np.cos(-zyx[2] if beta > 0 else zyx[2]), np.cos(combined))
    np.testing.assert_allclose(euler_zyx_to_matrix(zyx), r, atol=1e-12)


def test_near_gimbal_lock_round_trip_is_still_exact():
    for eps in (1e-13, 1e-11, 1e-9, 1e-7):
        r = euler_zyx_to_matrix([0.7, np.pi / 2 - eps, -0.4])
        zyx, singular = matrix_to_euler_zyx(r, return_singular=True)
        assert singular == (np.cos(np.pi / 2 - eps) < EULER_SINGULAR_COS)
        np.testing.assert_allclose(euler_zyx_to_matrix(zyx), r, atol=1e-12)


unit_axis = st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)).filter(
    lambda v: np.linalg.norm(v) > 0.1)


@settings(max_examples=300, deadline=None)
@given(unit_axis, st.floats(0, np.pi))
def test_axis_angle_round_trip(axis, theta):
    n = np.array(axis) / np.linalg.norm(axis)
    r = axis_angle_to_matrix(axis, theta)
    np.testing.assert_allclose(r, rodrigues(n, theta), atol=1e-13)
    back_axis, back_angle = matrix_to_axis_angle(r)
    np.testing.assert_allclose(axis_angle_to_matrix(back_axis, back_angle), r, atol=1e-12)
    assert abs(np.linalg.norm(back_axis) - 1) < 1e-12 and 0 <= back_angle <= np.pi
    if 1e-6 < theta < np.pi - 1e-6:  # away from the ends, axis and angle themselves come back
        np.testing.assert_allclose(back_axis, n, atol=1e-8)
        assert abs(back_angle - theta) < 1e-10


@pytest.mark.parametrize("theta", [0.0, 1e-12, 1e-8, np.pi - 1e-8, np.pi - 1e-12, np.pi])
def test_axis_angle_near_zero_and_near_pi(theta):
    n = np.array([2.0, -1.0, 0.5]) / np.linalg.norm([2.0, -1.0, 0.5])
    r = rodrigues(n, theta)
    axis, angle = matrix_to_axis_angle(r)
    assert abs(angle - theta) < 1e-9
    np.testing.assert_allclose(axis_angle_to_matrix(axis, angle), r, atol=1e-12)
    if theta > 0.5:  # near pi the axis is read from the symmetric part: n or -n
        assert abs(abs(axis @ n) - 1) < 1e-9
    if theta == 0.0:
        np.testing.assert_array_equal(axis, [0, 0, 1])


def test_non_rotations_are_rejected_with_a_reason():
    with pytest.raises(RotationError, match="reflection"):
        matrix_to_euler_zyx(np.diag([1.0, -1.0, 1.0]))
    with pytest.raises(RotationError, match=r"differs from I by 1.25"):
        matrix_to_axis_angle(np.diag([1.0, 1.0, 1.5]))  # 1.5**2 - 1
    with pytest.raises(RotationError, match="finite"):
        check_rotation(np.full((3, 3), np.nan))
    with pytest.raises(RotationError, match=r"matrix 1 of 2"):
        check_rotation([np.eye(3), 2 * np.eye(3)])
    with pytest.raises(RotationError, match=r"\(\.\.\., 3, 3\)"):
        check_rotation(np.eye(4))
    with pytest.raises(RotationError, match="non-zero"):
        axis_angle_to_matrix([0, 0, 0], 1.0)
    # slightly off (1e-9) is still a rotation under the default tolerance
    check_rotation(euler_zyx_to_matrix([0.1, 0.2, 0.3]) + 1e-9)


def test_batches():
    rng = np.random.default_rng(0)
    zyx = rng.uniform(-1, 1, size=(4, 5, 3))
    r = euler_zyx_to_matrix(zyx)
    assert r.shape == (4, 5, 3, 3)
    np.testing.assert_allclose(matrix_to_euler_zyx(r), zyx, atol=1e-12)
    axis, ang = matrix_to_axis_angle(r)
    assert axis.shape == (4, 5, 3) and ang.shape == (4, 5)
