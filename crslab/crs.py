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

import numpy as np

from crslab._core import ffi, lib
from crslab.arrays import as_rows, dptr, iptr

BASE_HEIGHT_IN: float = lib.CRS_BASE_HEIGHT_IN
"""Height of the shoulder axis above the DH base frame (in)."""
UPPER_ARM_IN: float = lib.CRS_UPPER_ARM_IN
"""Shoulder axis to elbow axis (in)."""
FOREARM_IN: float = lib.CRS_FOREARM_IN
"""Elbow axis to the end-effector point (in)."""
M_PER_IN: float = lib.CRS_M_PER_IN
"""Metres per inch (exact)."""

ENVELOPE_TH1_MAX_RAD: float = lib.CRS_ENVELOPE_TH1_MAX_RAD
"""The framework's safety envelope: |th1 DH| at most this (rad), ..."""
ENVELOPE_TH2_RAD: tuple[float, float] = (lib.CRS_ENVELOPE_TH2_MIN_RAD, lib.CRS_ENVELOPE_TH2_MAX_RAD)
"""... th2 DH within this range (rad), ..."""
ENVELOPE_TH3_RAD: tuple[float, float] = (lib.CRS_ENVELOPE_TH3_MIN_RAD, lib.CRS_ENVELOPE_TH3_MAX_RAD)
"""... th3 DH within this range (rad), ..."""
ENVELOPE_Z_MIN_IN: float = lib.CRS_ENVELOPE_Z_MIN_IN
"""... and the end effector at least this high (in)."""

IK_OK = lib.CRS_IK_OK
IK_UNREACHABLE = lib.CRS_IK_UNREACHABLE
IK_SHOULDER = lib.CRS_IK_SHOULDER
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


def _map3(func: object, values: object, name: str) -> np.ndarray:
    src = as_rows(values, 3, name)
    out = np.empty_like(src)
    func(dptr(src), dptr(out), src.size // 3)
    return out


def motor_to_dh(motor_rad: object) -> np.ndarray:
    """DH angles (rad) from motor angles (rad): th2 = th2M - pi/2, th3 = th3M - th2M + pi/2.

    >>> motor_to_dh([0.0, np.pi / 2, 0.0])
    array([0., 0., 0.])
    """
    return _map3(lib.crs_motor_to_dh_batch, motor_rad, "motor_rad")


def dh_to_motor(dh_rad: object) -> np.ndarray:
    """Motor angles (rad) from DH angles (rad); motor 3 is the forearm's absolute angle.

    >>> np.degrees(dh_to_motor(np.radians([0, -90, 90]))) + 0.0
    array([0., 0., 0.])
    """
    return _map3(lib.crs_dh_to_motor_batch, dh_rad, "dh_rad")


def fk(motor_rad: object) -> np.ndarray:
    """End-effector position (in) from motor angles (rad).

    >>> np.round(fk(np.radians([0, 0, -90])), 12) + 0.0     # straight up
    array([ 0.,  0., 30.])
    """
    return _map3(lib.crs_fk_motor_batch, motor_rad, "motor_rad")


def fk_dh(dh_rad: object) -> np.ndarray:
    """End-effector position (in) from DH angles (rad).

    >>> fk_dh([0.0, 0.0, 0.0])
    array([20.,  0., 10.])
    """
    return _map3(lib.crs_fk_dh_batch, dh_rad, "dh_rad")


def fk_pose_dh(dh_rad: object) -> np.ndarray:
    """4x4 pose of the end-effector frame (DH frame 3) from DH angles (rad); translation in in.

    Built link by link from the DH table, so it is an independent check on :func:`fk_dh`.

    >>> fk_pose_dh([0.0, 0.0, 0.0])[:3, 3]
    array([20.,  0., 10.])
    """
    src = as_rows(dh_rad, 3, "dh_rad")
    rows = src.reshape(-1, 3)
    out = np.empty((rows.shape[0], 16))
    pose = ffi.new("double[16]")
    for i, q in enumerate(rows):  # the 4x4 form is for inspection, not for batches
        lib.crs_fk_pose_dh(dptr(np.ascontiguousarray(q)), pose)
        out[i] = ffi.unpack(pose, 16)
    return out.reshape(src.shape[:-1] + (4, 4))


def _ik(func: object, xyz_in: object, elbow: str) -> tuple[np.ndarray, np.ndarray]:
    if elbow not in ("up", "down"):
        raise ValueError(f"elbow must be 'up' or 'down', got {elbow!r}")
    src = as_rows(xyz_in, 3, "xyz_in")
    out = np.empty_like(src)
    status = np.empty(src.shape[:-1], dtype=np.int32)
    func(dptr(src), 1 if elbow == "up" else 0, dptr(out), iptr(status), src.size // 3)
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
    return _ik(lib.crs_ik_motor_batch, xyz_in, elbow)


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
    out, status = _ik(lib.crs_ik_dh_batch, xyz_in, elbow)
    _raise_if_bad(xyz_in, status)
    return out


def outside_envelope(motor_rad: object) -> np.ndarray:
    """True where motor angles (rad) lie outside the framework's safety envelope.

    >>> outside_envelope([[0.0, 0.0, 0.0], [0.0, np.pi / 2, 0.0]])   # motor zero, DH zero
    array([False,  True])
    """
    src = as_rows(motor_rad, 3, "motor_rad")
    out = np.empty(src.shape[:-1], dtype=np.int32)
    lib.crs_outside_envelope_motor_batch(dptr(src), iptr(out), src.size // 3)
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
    lib.crs_jacobian_motor_batch(dptr(src), dptr(out), src.size // 3)
    return out
