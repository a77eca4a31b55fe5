"""Rotations as the course writes them, over the C core (``csrc/kin/rotation.h``).

*Euler ZYX* ``(alpha, beta, gamma)`` means ``R = Rot_z(alpha) Rot_y(beta) Rot_x(gamma)`` (yaw,
pitch, roll; seed 001). *Axis-angle* ``(n, theta)`` is Rodrigues' formula with a unit axis and
``theta`` in ``[0, pi]``. Arrays are batch-shaped: ``(..., 3)`` angles, ``(..., 3, 3)`` matrices.

Matrix inputs are checked first: a matrix that is not a rotation (not orthonormal within
``tol``, a reflection, or not finite) raises :class:`RotationError` naming the first bad one.

>>> import numpy as np
>>> R = euler_zyx_to_matrix(np.radians([90, 0, 0]))
>>> R.round(12) + 0.0
array([[ 0., -1.,  0.],
       [ 1.,  0.,  0.],
       [ 0.,  0.,  1.]])
>>> np.degrees(matrix_to_euler_zyx(R)).round(9) + 0.0
array([90.,  0.,  0.])
>>> axis, angle = matrix_to_axis_angle(R)
>>> axis.round(12) + 0.0, float(np.degrees(angle).round(9))
(array([0., 0., 1.]), 90.0)
"""

from __future__ import annotations

import numpy as np

from crslab import _bindings
from crslab._bindings import constants
from crslab.arrays import as_rows

CHECK_TOL: float = constants.ROT_CHECK_TOL
"""Default tolerance on the entries of ``R R^T - I``."""
EULER_SINGULAR_COS: float = constants.ROT_EULER_SINGULAR_COS
"""``cos(beta)`` below this is gimbal lock (see :func:`matrix_to_euler_zyx`)."""


class RotationError(ValueError):
    """A matrix that is not a rotation, or an axis with no direction."""


def _matrices(r: object, name: str) -> np.ndarray:
    arr = np.ascontiguousarray(r, dtype=np.float64)
    if arr.ndim < 2 or arr.shape[-2:] != (3, 3):
        raise RotationError(f"{name} must have shape (..., 3, 3), got {arr.shape}")
    return arr


def rotation_status(r: object, tol: float = CHECK_TOL) -> tuple[np.ndarray, np.ndarray]:
    """Per matrix: the C status (``ROT_OK`` ...) and ``max |R R^T - I|``."""
    arr = _matrices(r, "R")
    status = np.empty(arr.shape[:-2], dtype=np.int32)
    deviation = np.empty(arr.shape[:-2])
    _bindings.rotation_check(arr, tol, status, deviation, arr.size // 9)
    return status, deviation


def check_rotation(r: object, tol: float = CHECK_TOL) -> np.ndarray:
    """Return ``r`` as a float array if every matrix is a rotation, else raise :class:`RotationError`.

    >>> check_rotation(np.diag([1.0, 1.0, -1.0]))
    Traceback (most recent call last):
    ...
    crslab.rotation.RotationError: not a rotation matrix: det = -1 (a reflection)
    >>> check_rotation([[1, 0, 0], [0, 1, 0], [0, 0.1, 1]])
    Traceback (most recent call last):
    ...
    crslab.rotation.RotationError: not a rotation matrix: R R^T differs from I by 0.1 (tolerance 1e-06)
    """
    arr = _matrices(r, "R")
    status, deviation = rotation_status(arr, tol)
    bad = np.flatnonzero(status.ravel() != constants.ROT_OK)
    if bad.size:
        i = int(bad[0])
        where = f" (matrix {i} of {status.size})" if status.size > 1 else ""
        code = int(status.ravel()[i])
        why = {
            constants.ROT_NOT_FINITE: "an entry is not a finite number",
            constants.ROT_NOT_ORTHONORMAL: f"R R^T differs from I by {deviation.ravel()[i]:.3g} "
            f"(tolerance {tol:g})",
            constants.ROT_REFLECTION: "det = -1 (a reflection)",
        }[code]
        raise RotationError(f"not a rotation matrix{where}: {why}")
    return arr


def euler_zyx_to_matrix(zyx_rad: object) -> np.ndarray:
    """``Rot_z(alpha) Rot_y(beta) Rot_x(gamma)`` for Euler ZYX angles (rad), ``(..., 3, 3)``."""
    src = as_rows(zyx_rad, 3, "zyx_rad")
    out = np.empty(src.shape[:-1] + (3, 3))
    _bindings.rotation_from_euler_zyx(src, out, src.size // 3)
    return out


def matrix_to_euler_zyx(r: object, tol: float = CHECK_TOL, *, return_singular: bool = False) -> object:
    """Euler ZYX angles (rad) of rotation matrices, with ``beta`` in ``[-pi/2, pi/2]``.

    The singular case (gimbal lock, ``cos(beta) < EULER_SINGULAR_COS``): only ``alpha - gamma``
    (beta = +pi/2) or ``alpha + gamma`` (beta = -pi/2) is defined, so ``alpha = 0`` and ``gamma``
    carries the whole turn; :func:`euler_zyx_to_matrix` still gives the matrix back. With
    ``return_singular=True`` the result is ``(angles, singular)``.

    >>> R = euler_zyx_to_matrix(np.radians([30, 90, 10]))      # gimbal lock
    >>> zyx, singular = matrix_to_euler_zyx(R, return_singular=True)
    >>> np.degrees(zyx).round(6) + 0.0, bool(singular)
    (array([  0.,  90., -20.]), True)
    """
    arr = check_rotation(r, tol)
    out = np.empty(arr.shape[:-2] + (3,))
    singular = np.empty(arr.shape[:-2], dtype=np.int32)
    _bindings.rotation_to_euler_zyx(arr, out, singular, arr.size // 9)
    return (out, singular.astype(bool)) if return_singular else out


def axis_angle_to_matrix(axis: object, angle_rad: object) -> np.ndarray:
    """Rotation matrices from axes (normalised here) and angles (rad), ``(..., 3, 3)``.

    >>> axis_angle_to_matrix([0, 0, 2], np.pi).round(12) + 0.0
    array([[-1.,  0.,  0.],
           [ 0., -1.,  0.],
           [ 0.,  0.,  1.]])
    """
    ax = as_rows(axis, 3, "axis")
    ang = np.ascontiguousarray(np.broadcast_to(np.asarray(angle_rad, dtype=np.float64), ax.shape[:-1]))
    out = np.empty(ax.shape[:-1] + (3, 3))
    status = np.empty(ax.shape[:-1], dtype=np.int32)
    _bindings.rotation_from_axis_angle(ax, ang, out, status, ax.size // 3)
    if np.any(status != constants.ROT_OK):
        raise RotationError("axis-angle needs a non-zero, finite axis and a finite angle")
    return out


def matrix_to_axis_angle(r: object, tol: float = CHECK_TOL) -> tuple[np.ndarray, np.ndarray]:
    """Unit axes ``(..., 3)`` and angles ``(...)`` in ``[0, pi]`` (rad) of rotation matrices.

    The identity gives the axis ``(0, 0, 1)`` and angle 0. Near ``pi`` the axis is read from the
    symmetric part of ``R`` and stays accurate; at exactly ``pi``, ``n`` and ``-n`` are the same
    rotation and either may be returned.
    """
    arr = check_rotation(r, tol)
    axis = np.empty(arr.shape[:-2] + (3,))
    angle = np.empty(arr.shape[:-2])
    _bindings.rotation_to_axis_angle(arr, axis, angle, arr.size // 9)
    return axis, angle
