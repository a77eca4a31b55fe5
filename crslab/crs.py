"""Kinematics of the CRS arm, over the C core, numpy in and out.

Units: positions in inches (the course's unit), angles in radians. Every function takes an
array of shape ``(..., 3)`` (one row per pose) and returns the same leading shape, with no
Python loop over rows.

*Motor angles* are what the lab's ``lab()`` receives from the encoders; *DH angles* follow the
course's DH table. Like the lab, :func:`fk` takes motor angles and :func:`ik` returns motor
angles, so ``fk(ik(p)) == p``; :func:`fk_dh` and :func:`ik_dh` are the DH-angle variants.

>>> import numpy as np
>>> fk(np.zeros(3))                       # motor zero: upper arm up, forearm level
array([10.,  0., 20.])
>>> np.round(fk(np.radians([0, 90, 0])), 12) + 0.0   # DH zero: arm stretched level
array([20.,  0., 10.])
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from crslab import _bindings
from crslab._bindings import constants
from crslab.arrays import as_rows

BASE_HEIGHT_IN: float = constants.CRS_BASE_HEIGHT_IN
"""Height of the shoulder axis above the DH base frame (in)."""
UPPER_ARM_IN: float = constants.CRS_UPPER_ARM_IN
"""Shoulder axis to elbow axis (in)."""
FOREARM_IN: float = constants.CRS_FOREARM_IN
"""Elbow axis to the end-effector point (in)."""
M_PER_IN: float = constants.CRS_M_PER_IN
"""Metres per inch (exact)."""

ENVELOPE_TH1_MAX_RAD: float = constants.CRS_ENVELOPE_TH1_MAX_RAD
"""The framework's safety envelope: |th1 DH| at most this (rad), ..."""
ENVELOPE_TH2_RAD: tuple[float, float] = (constants.CRS_ENVELOPE_TH2_MIN_RAD,
                                         constants.CRS_ENVELOPE_TH2_MAX_RAD)
"""... th2 DH within this range (rad), ..."""
ENVELOPE_TH3_RAD: tuple[float, float] = (constants.CRS_ENVELOPE_TH3_MIN_RAD,
                                         constants.CRS_ENVELOPE_TH3_MAX_RAD)
"""... th3 DH within this range (rad), ..."""
ENVELOPE_Z_MIN_IN: float = constants.CRS_ENVELOPE_Z_MIN_IN
"""... and the end effector at least this high (in)."""

IK_OK = constants.CRS_IK_OK
IK_UNREACHABLE = constants.CRS_IK_UNREACHABLE
IK_SHOULDER = constants.CRS_IK_SHOULDER
IK_STATUS_TEXT = {
    IK_OK: "ok",
    IK_UNREACHABLE: f"out of reach (farther than {UPPER_ARM_IN + FOREARM_IN:g} in from the shoulder)",
    IK_SHOULDER: "on the shoulder centre (any shoulder angle is a solution)",
}


class UnreachableError(ValueError):
    """Raised by :func:`ik` when a target has no exact solution.

    ``status`` holds the per-row IK status codes (``IK_OK``, ``IK_UNREACHABLE``, ``IK_SHOULDER``).
    """

    def __init__(self, message: str, status: np.ndarray) -> None:
        super().__init__(message)
        self.status = status


def _map3(func: Callable[[np.ndarray, np.ndarray, int], None], values: object, name: str) -> np.ndarray:
    src = as_rows(values, 3, name)
    out = np.empty_like(src)
    func(src, out, src.size // 3)
    return out


def motor_to_dh(motor_rad: object) -> np.ndarray:
    """DH angles (rad) from motor angles (rad): th2 = th2M - pi/2, th3 = th3M - th2M + pi/2.

    >>> motor_to_dh([0.0, np.pi / 2, 0.0])
    array([0., 0., 0.])
    """
    return _map3(_bindings.arm_motor_to_dh, motor_rad, "motor_rad")


def dh_to_motor(dh_rad: object) -> np.ndarray:
    """Motor angles (rad) from DH angles (rad); motor 3 is the forearm's absolute angle.

    >>> np.degrees(dh_to_motor(np.radians([0, -90, 90]))) + 0.0
    array([0., 0., 0.])
    """
    return _map3(_bindings.arm_dh_to_motor, dh_rad, "dh_rad")


def fk(motor_rad: object) -> np.ndarray:
    """End-effector position (in) from motor angles (rad).

    >>> np.round(fk(np.radians([0, 0, -90])), 12) + 0.0     # straight up
    array([ 0.,  0., 30.])
    """
    return _map3(_bindings.arm_fk_motor, motor_rad, "motor_rad")


def fk_dh(dh_rad: object) -> np.ndarray:
    """End-effector position (in) from DH angles (rad).

    >>> fk_dh([0.0, 0.0, 0.0])
    array([20.,  0., 10.])
    """
    return _map3(_bindings.arm_fk_dh, dh_rad, "dh_rad")


def fk_pose_dh(dh_rad: object) -> np.ndarray:
    """4x4 pose of the end-effector frame (DH frame 3) from DH angles (rad); translation in in.

    Built link by link from the DH table, so it is an independent check on :func:`fk_dh`.

    >>> fk_pose_dh([0.0, 0.0, 0.0])[:3, 3]
    array([20.,  0., 10.])
    """
    src = as_rows(dh_rad, 3, "dh_rad")
    rows = src.reshape(-1, 3)
    out = np.empty((rows.shape[0], 16))
    for i, q in enumerate(rows):  # the 4x4 form is for inspection, not for batches
        _bindings.arm_fk_pose_dh(np.ascontiguousarray(q), out[i])
    return out.reshape(src.shape[:-1] + (4, 4))


def _ik(func: Callable[..., None], xyz_in: object, elbow: str) -> tuple[np.ndarray, np.ndarray]:
    if elbow not in ("up", "down"):
        raise ValueError(f"elbow must be 'up' or 'down', got {elbow!r}")
    src = as_rows(xyz_in, 3, "xyz_in")
    out = np.empty_like(src)
    status = np.empty(src.shape[:-1], dtype=np.int32)
    func(src, elbow == "up", out, status, src.size // 3)
    return out, status


def _raise_if_bad(xyz_in: object, status: np.ndarray) -> None:
    bad = np.flatnonzero(status.ravel() != IK_OK)
    if bad.size:
        rows = np.asarray(xyz_in, dtype=float).reshape(-1, 3)
        i = int(bad[0])
        where = "" if status.ndim == 0 else f"row {i}: "
        x, y, z = rows[i]
        raise UnreachableError(
            f"{where}target ({x:.4g}, {y:.4g}, {z:.4g}) in is "
            f"{IK_STATUS_TEXT[int(status.ravel()[i])]}"
            + (f" ({bad.size} of {status.size} rows)" if status.size > 1 else ""),
            status,
        )


def ik_with_status(xyz_in: object, elbow: str = "up") -> tuple[np.ndarray, np.ndarray]:
    """Motor angles (rad) for targets (in), with a per-row status instead of an exception.

    Rows whose status is not ``IK_OK`` hold a defined pose, never NaN: an out-of-reach target
    gets the stretched arm pointing at it, the shoulder centre gets the folded arm.

    >>> q, status = ik_with_status([[10, 0, 20], [40, 0, 10]])
    >>> status.tolist()
    [0, 1]
    >>> np.round(fk(q), 9) + 0.0
    array([[10.,  0., 20.],
           [20.,  0., 10.]])
    """
    return _ik(_bindings.arm_ik_motor, xyz_in, elbow)


def ik(xyz_in: object, elbow: str = "up") -> np.ndarray:
    """Motor angles (rad) that put the end effector at ``xyz_in`` (in).

    ``elbow="up"`` (the labs' choice) gives th3 DH >= 0; ``"down"`` the mirror solution. On the
    base axis (x = y = 0) joint 1 is 0. Raises :class:`UnreachableError` naming the first bad
    row when any target has no exact solution; use :func:`ik_with_status` to get per-row status.

    >>> np.degrees(ik([10.0, 0.0, 20.0])).round(9) + 0.0
    array([0., 0., 0.])
    >>> ik([0.0, 0.0, 31.0])
    Traceback (most recent call last):
    ...
    crslab.crs.UnreachableError: target (0, 0, 31) in is out of reach (farther than 20 in ...)
    """
    out, status = ik_with_status(xyz_in, elbow)
    _raise_if_bad(xyz_in, status)
    return out


def ik_dh(xyz_in: object, elbow: str = "up") -> np.ndarray:
    """DH angles (rad) that put the end effector at ``xyz_in`` (in); see :func:`ik`.

    >>> np.degrees(ik_dh([20.0, 0.0, 10.0])) + 0.0
    array([0., 0., 0.])
    """
    out, status = _ik(_bindings.arm_ik_dh, xyz_in, elbow)
    _raise_if_bad(xyz_in, status)
    return out


def outside_envelope(motor_rad: object) -> np.ndarray:
    """True where motor angles (rad) lie outside the framework's safety envelope.

    >>> outside_envelope([[0.0, 0.0, 0.0], [0.0, np.pi / 2, 0.0]])   # motor zero, DH zero
    array([False,  True])
    """
    src = as_rows(motor_rad, 3, "motor_rad")
    out = np.empty(src.shape[:-1], dtype=np.int32)
    _bindings.arm_outside_envelope(src, out, src.size // 3)
    return out.astype(bool)


def jacobian(motor_rad: object) -> np.ndarray:
    """d(xyz in inches)/d(motor angles in rad), shape ``(..., 3, 3)``.

    >>> jacobian([0.0, 0.0, 0.0]) + 0.0
    array([[  0.,  10.,   0.],
           [ 10.,   0.,   0.],
           [  0.,   0., -10.]])
    """
    src = as_rows(motor_rad, 3, "motor_rad")
    out = np.empty(src.shape[:-1] + (3, 3))
    _bindings.arm_jacobian_motor(src, out, src.size // 3)
    return out
