"""DH chains (crslab.chain) against seed 002's numbers and an independent numpy implementation."""

import numpy as np
import pytest

from crslab import robots
from crslab.chain import Chain


def dh_standard(a, alpha, d, theta):
    """Rot_z(theta) Trans_z(d) Trans_x(a) Rot_x(alpha), written out as seed 001/002 print it."""
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d],
                     [0, 0, 0, 1.0]])


def rot_x(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def rot_z(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def trans(x, y, z):
    t = np.eye(4)
    t[:3, 3] = x, y, z
    return t


def dh_modified(a, alpha, d, theta):
    """Craig's link transform as the product of its four elementary motions."""
    return rot_x(alpha) @ trans(a, 0, 0) @ rot_z(theta) @ trans(0, 0, d)


def numpy_frames(chain, q):
    """Every frame, one 4x4 product per row: the straightforward way."""
    link = dh_modified if chain.convention == "modified" else dh_standard
    t = np.eye(4) if chain.base is None else chain.base.copy()
    frames = [t]
    j = 0
    for i in range(chain.n_rows):
        theta = chain.theta_rad[i]
        if chain.joint_types[i] == "revolute":
            theta += q[j]
            j += 1
        t = t @ link(chain.a[i], chain.alpha_rad[i], chain.d[i], theta)
        frames.append(t)
    frames.append(t if chain.tool is None else t @ chain.tool)
    return np.array(frames)


PANDA_Q = np.array([0, 0, 0, -np.pi / 2, 0, np.pi / 2, np.pi / 4])


def test_panda_seed_002_end_effector_and_joint_centres():
    """Seed 002's worked configuration: the end effector and the eight joint centres (m)."""
    panda = robots.load("panda")
    pose = panda.fk(PANDA_Q)
    np.testing.assert_allclose(pose[:3, 3], [0.5545, 0, 0.5215], atol=1e-12)
    np.testing.assert_allclose(pose[:3, :3], np.diag([1.0, -1.0, -1.0]), atol=1e-12)
    centres = [(0, 0, 0.141), (0, 0, 0.333), (0, 0, 0.528), (0.0825, 0, 0.649), (0.2075, 0, 0.7315),
               (0.4665, 0.015, 0.7315), (0.5545, 0, 0.6805), (0.5545, 0, 0.5215)]
    np.testing.assert_allclose(panda.joint_centres(PANDA_Q), centres, atol=1e-12)


def test_standard_and_modified_panda_agree_on_the_end_effector_and_flange():
    std, mdh = robots.load("panda"), robots.load("panda_mdh")
    q = np.random.default_rng(3).uniform(std.chain.lower, std.chain.upper, size=(500, 7))
    np.testing.assert_allclose(std.fk(q), mdh.fk(q), atol=1e-12)
    # the flange is the modified table's last frame; the standard table reaches it 0.103 m before
    # its end effector, turned back by pi/4 (the inverse of the modified file's tool)
    flange_std = std.fk(q) @ np.linalg.inv(mdh.chain.tool)
    np.testing.assert_allclose(mdh.chain.frames(q)[:, -2], flange_std, atol=1e-12)


@pytest.mark.parametrize("name", robots.names())
def test_every_robot_matches_numpy_dh_products(name):
    robot = robots.load(name)
    c = robot.chain
    lo = np.where(np.isfinite(c.lower), c.lower, -np.pi)
    hi = np.where(np.isfinite(c.upper), c.upper, np.pi)
    q = np.random.default_rng(len(name)).uniform(lo, hi, size=(50, c.n_joints))
    expected = np.array([numpy_frames(c, qi) for qi in q])
    np.testing.assert_allclose(c.frames(q), expected, atol=1e-12)
    np.testing.assert_allclose(c.fk(q), expected[:, -1], atol=1e-12)


def test_crs_file_agrees_with_the_c_core_crs_arm():
    from crslab import crs

    dh = np.random.default_rng(0).uniform(-3, 3, size=(200, 3))
    np.testing.assert_allclose(robots.load("crs").fk(dh)[:, :3, 3], crs.fk_dh(dh), atol=1e-12)


def numeric_jacobian(chain, q, h=1e-6):
    """Central differences of position, and of orientation via R(q+h) R(q-h)^T (small angle)."""
    cols = []
    for j in range(chain.n_joints):
        dq = np.zeros(chain.n_joints)
        dq[j] = h
        tp, tm = chain.fk(q + dq), chain.fk(q - dq)
        dr = tp[:3, :3] @ tm[:3, :3].T
        w = np.array([dr[2, 1] - dr[1, 2], dr[0, 2] - dr[2, 0], dr[1, 0] - dr[0, 1]]) / 2
        cols.append(np.concatenate([(tp[:3, 3] - tm[:3, 3]) / (2 * h), w / (2 * h)]))
    return np.array(cols).T


@pytest.mark.parametrize("name", ["panda", "panda_mdh", "arm7r", "rrr", "planar3r", "crs"])
def test_geometric_jacobian_matches_finite_differences(name):
    chain = robots.load(name).chain
    rng = np.random.default_rng(11)
    for _ in range(5):
        q = rng.uniform(-2, 2, chain.n_joints)
        np.testing.assert_allclose(chain.jacobian(q), numeric_jacobian(chain, q), atol=1e-7)


def test_base_and_tool_wrap_the_chain():
    base = trans(0.1, -0.2, 0.3) @ rot_z(0.7)
    tool = trans(0, 0.05, 0.1) @ rot_x(-0.4)
    bare = Chain(a=[0.3, 0.2], alpha_rad=[0.5, -1.0], d=[0.1, 0.0], theta_rad=[0.2, 0.0])
    dressed = Chain(a=[0.3, 0.2], alpha_rad=[0.5, -1.0], d=[0.1, 0.0], theta_rad=[0.2, 0.0], base=base,
                    tool=tool)
    q = np.random.default_rng(5).uniform(-3, 3, size=(20, 2))
    np.testing.assert_allclose(dressed.fk(q), base @ bare.fk(q) @ tool, atol=1e-14)
    np.testing.assert_allclose(dressed.jacobian(q)[:, 3:], np.einsum("ij,njk->nik", base[:3, :3],
                                                                     bare.jacobian(q)[:, 3:]), atol=1e-14)


def test_batches_keep_their_shape_and_match_single_calls():
    chain = robots.load("panda").chain
    q = np.random.default_rng(2).uniform(-1, 1, size=(3, 4, 7))
    assert chain.fk(q).shape == (3, 4, 4, 4)
    assert chain.frames(q).shape == (3, 4, 10, 4, 4)
    assert chain.jacobian(q).shape == (3, 4, 6, 7)
    np.testing.assert_allclose(chain.fk(q)[1, 2], chain.fk(q[1, 2]), atol=1e-15)  # SIMD vs scalar sin
    big = np.random.default_rng(2).uniform(-1, 1, size=(3000, 7))  # spans several C blocks
    np.testing.assert_allclose(chain.fk(big)[::97], [numpy_frames(chain, x)[-1] for x in big[::97]],
                               atol=1e-12)


def test_bad_tables_are_refused():
    with pytest.raises(ValueError, match="equally long"):
        Chain(a=[1, 2], alpha_rad=[0], d=[0, 0])
    with pytest.raises(ValueError, match="convention"):
        Chain(a=[1], alpha_rad=[0], d=[0], convention="craig")
    with pytest.raises(ValueError, match="finite"):
        Chain(a=[np.nan], alpha_rad=[0], d=[0])
    with pytest.raises(ValueError, match="lower limit"):
        Chain(a=[1], alpha_rad=[0], d=[0], lower=[1.0], upper=[0.0])
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 2\)"):
        Chain(a=[1, 1], alpha_rad=[0, 0], d=[0, 0]).fk([1.0, 2.0, 3.0])
