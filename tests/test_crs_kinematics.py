"""The CRS arm's kinematics (crslab.crs) against hand-derived numbers and independent math."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from crslab import crs


def deg(*a):
    return np.radians(a)


# docs/framework.md section 10's checks, derived by hand from the DH table (inches).
@pytest.mark.parametrize(
    "motor_deg, xyz_in",
    [
        ((0, 0, 0), (10, 0, 20)),  # motor zero
        ((0, 90, 0), (20, 0, 10)),  # DH zero
        ((0, 0, -90), (0, 0, 30)),  # straight up
        ((90, 90, 0), (0, 20, 10)),  # DH zero turned a quarter turn about the base
    ],
)
def test_fk_known_poses(motor_deg, xyz_in):
    np.testing.assert_allclose(crs.fk(deg(*motor_deg)), xyz_in, atol=1e-12)


# A Lab 1 report's Tera Term tables: what a real board printed with %.2f, motor angles (deg) and
# xyz (in) (docs/framework.md section 10; the report's "-87.06" is a slip for 87.06, the DH-zero
# pose).
# The board printed float32 values of unrounded angles, so FK of the printed (rounded) angles,
# printed the same way, agrees to one unit in the last printed digit (0.01 in).
@pytest.mark.parametrize(
    "motor_deg, printed_xyz_in",
    [((1.41, 87.06, -1.99), (19.97, 0.49, 10.85)), ((-0.93, 2.86, -79.60), (2.30, -0.03, 29.82))],
)
def test_fk_matches_real_board_printout(motor_deg, printed_xyz_in):
    as_printed = np.round(crs.fk(deg(*motor_deg)), 2)
    np.testing.assert_allclose(as_printed, printed_xyz_in, atol=0.01 + 1e-9)


def numpy_fk_dh(dh):
    """Independent FK: multiply the three standard DH matrices in numpy."""

    def a(a_, alpha, d, th):
        ct, st, ca, sa = np.cos(th), np.sin(th), np.cos(alpha), np.sin(alpha)
        return np.array(
            [[ct, -st * ca, st * sa, a_ * ct], [st, ct * ca, -ct * sa, a_ * st], [0, sa, ca, d],
             [0, 0, 0, 1]]
        )

    return a(0, -np.pi / 2, 10, dh[0]) @ a(10, 0, 0, dh[1]) @ a(10, 0, 0, dh[2])


def test_fk_agrees_with_dh_product_and_pose():
    rng = np.random.default_rng(7)
    dh = rng.uniform(-np.pi, np.pi, size=(200, 3))
    expected = np.array([numpy_fk_dh(q)[:3, 3] for q in dh])
    np.testing.assert_allclose(crs.fk_dh(dh), expected, atol=1e-12)
    np.testing.assert_allclose(crs.fk(crs.dh_to_motor(dh)), expected, atol=1e-12)
    np.testing.assert_allclose(crs.fk_pose_dh(dh[:20]), [numpy_fk_dh(q) for q in dh[:20]],
                               atol=1e-12)


def test_batch_shapes_are_kept():
    q = np.zeros((4, 5, 3))
    assert crs.fk(q).shape == (4, 5, 3)
    assert crs.jacobian(q).shape == (4, 5, 3, 3)
    assert crs.ik_with_status(crs.fk(q))[1].shape == (4, 5)
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 3\)"):
        crs.fk(np.zeros((4, 2)))


def test_motor_dh_round_trip():
    rng = np.random.default_rng(1)
    q = rng.uniform(-4, 4, size=(1000, 3))
    np.testing.assert_allclose(crs.dh_to_motor(crs.motor_to_dh(q)), q, atol=1e-15)
    np.testing.assert_allclose(crs.motor_to_dh(crs.dh_to_motor(q)), q, atol=1e-15)
    # the relation itself, by hand: th3 DH = th3M - th2M + pi/2
    np.testing.assert_allclose(crs.motor_to_dh([0.3, 0.5, 0.7]), [0.3, 0.5 - np.pi / 2,
                                                                   0.7 - 0.5 + np.pi / 2])


reachable = st.tuples(
    st.floats(-np.pi, np.pi),  # th1
    st.floats(-np.pi / 2, np.pi / 2),  # direction from the shoulder
    st.floats(0.05, 19.999),  # distance from the shoulder, in
)


@settings(max_examples=300, deadline=None)
@given(st.lists(reachable, min_size=1, max_size=20), st.sampled_from(["up", "down"]))
def test_fk_of_ik_is_identity(targets, elbow):
    t = np.array(targets)
    r = t[:, 2] * np.cos(t[:, 1])
    p = np.stack([r * np.cos(t[:, 0]), r * np.sin(t[:, 0]), 10 + t[:, 2] * np.sin(t[:, 1])], -1)
    q = crs.ik(p, elbow=elbow)
    np.testing.assert_allclose(crs.fk(q), p, atol=1e-9)
    th3_dh = crs.motor_to_dh(q)[:, 2]
    assert np.all(th3_dh >= 0) if elbow == "up" else np.all(th3_dh <= 0)


def test_fk_of_ik_thousands_of_points():
    rng = np.random.default_rng(3)
    n = 5000
    d = 20 * np.cbrt(rng.uniform(1e-6, 1, n))
    v = rng.normal(size=(n, 3))
    p = v / np.linalg.norm(v, axis=1, keepdims=True) * d[:, None] + [0, 0, 10]
    for elbow in ("up", "down"):
        np.testing.assert_allclose(crs.fk(crs.ik(p, elbow=elbow)), p, atol=1e-9)


def test_elbow_up_matches_lab_formula():
    # The Lab 1 report's IK (docs/framework.md section 10): th2 = -gamma - alpha, th3 = pi - beta.
    x, y, z = 12.0, 5.0, 14.0
    r = np.hypot(x, y)
    gamma = np.arctan2(z - 10, r)
    dist2 = r * r + (z - 10) ** 2
    alpha = np.arccos(dist2 / (20 * np.sqrt(dist2)))
    beta = np.arccos((200 - dist2) / 200)
    np.testing.assert_allclose(crs.ik_dh([x, y, z]), [np.arctan2(y, x), -gamma - alpha, np.pi - beta])


def test_unreachable_on_axis_and_boundary_are_defined():
    q, status = crs.ik_with_status([[0, 0, 31], [25, 0, 10], [0, 0, 10], [0, 0, 30], [20, 0, 10]])
    assert not np.isnan(q).any()
    assert status.tolist() == [crs.IK_UNREACHABLE, crs.IK_UNREACHABLE, crs.IK_SHOULDER,
                               crs.IK_OK, crs.IK_OK]
    # unreachable: the stretched arm points at the target (nearest reachable point)
    np.testing.assert_allclose(crs.fk(q[0]), [0, 0, 30], atol=1e-12)
    np.testing.assert_allclose(crs.fk(q[1]), [20, 0, 10], atol=1e-12)
    # shoulder centre: folded arm, end effector exactly there
    np.testing.assert_allclose(crs.fk(q[2]), [0, 0, 10], atol=1e-12)
    # on the base axis th1 = 0 by convention; boundary points are exact
    assert q[3, 0] == 0.0
    # rounding dust next to the axis does not swing joint 1 around (straight up prints 0, not -180)
    assert crs.ik([-1e-15, -1e-15, 30.0])[0] == 0.0
    np.testing.assert_allclose(crs.fk(q[3:]), [[0, 0, 30], [20, 0, 10]], atol=1e-9)
    with pytest.raises(crs.UnreachableError, match=r"row 0: target \(0, 0, 31\).*2 of 5 rows"):
        crs.ik([[0, 0, 31], [0, 0, 30], [25, 0, 10], [10, 0, 20], [11, 0, 20]])
    with pytest.raises(ValueError, match="elbow"):
        crs.ik([10, 0, 20], elbow="sideways")


def test_jacobian_matches_finite_differences():
    rng = np.random.default_rng(5)
    q = rng.uniform(-np.pi, np.pi, size=(100, 3))
    h = 1e-6
    fd = np.stack([(crs.fk(q + h * e) - crs.fk(q - h * e)) / (2 * h) for e in np.eye(3)], -1)
    np.testing.assert_allclose(crs.jacobian(q), fd, atol=1e-7)


def test_dimensions_come_from_the_c_core():
    assert (crs.BASE_HEIGHT_IN, crs.UPPER_ARM_IN, crs.FOREARM_IN) == (10.0, 10.0, 10.0)
    assert crs.M_PER_IN == 0.0254


def test_safety_envelope_by_hand():
    # docs/framework.md section 3: |th1| <= 0.6667 pi, th2 in [-2.3, 0.15], th3 in [0.15, 2.3],
    # z >= 4 in
    rest = [0.0, -0.42, 0.24]
    th3_edge = crs.dh_to_motor([0.0, -1.0, 0.1501])  # th3 DH just above its lower bound: inside
    cases = {
        "rest": (rest, False),
        "motor zero": ([0.0, 0.0, 0.0], False),
        "DH zero (th3 = 0)": ([0.0, np.pi / 2, 0.0], True),
        "straight up (th3 = 0)": ([0.0, 0.0, -np.pi / 2], True),
        "th1 just inside": ([0.6666 * np.pi, 0.0, 0.0], False),
        "th1 just outside": ([-0.6668 * np.pi, 0.0, 0.0], True),
        "th3 just inside": (th3_edge, False),
        "th3 below its bound": (crs.dh_to_motor([0.0, -1.0, 0.149]), True),
        # th2 DH = 0.1, th3 DH = 2.0: inside the angle ranges, but the hand is at z < 4 in
        "below 4 in": (crs.dh_to_motor([0.0, 0.1, 2.0]), True),
    }
    for name, (motor, outside) in cases.items():
        assert bool(crs.outside_envelope(motor)) == outside, name
    assert crs.fk(crs.dh_to_motor([0.0, 0.1, 2.0]))[2] < 4.0
    assert crs.ENVELOPE_TH1_MAX_RAD == pytest.approx(0.6667 * np.pi)
