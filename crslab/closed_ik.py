"""Closed-form IK of the spatial RRR arm (seed 003) and the planar 3R arm (seeds 001, 002), over
the C core (``csrc/kin/closed_ik.h``): every solution at once, joint limits applied, the singular
cases defined. Angles in rad, lengths in the robot's unit.

Each solver returns :class:`Solutions`: ``q`` of shape ``(..., slots, 3)``, ``status`` per slot
(``OK``, ``OUT_OF_LIMITS``, ``UNREACHABLE``) and ``singular`` flags per target. Unusable slots
still hold finite angles (for an unreachable target, the arm stretched toward it), never NaN.

>>> import numpy as np
>>> lim = np.array([np.pi, np.pi / 2, np.pi])
>>> sol = rrr_ik((0.0, 10.0, 5.0, 5.0), [17.85, 2.698, 5.219], -lim, lim)    # seed 003's point
>>> sol.q[sol.status == OK].round(2)          # the seed's angles, and the other elbow
array([[ 0.15,  0.29,  0.57],
       [ 0.15,  0.86, -0.57]])
>>> sol.status.tolist()                       # reaching back over the base: too far
[0, 0, 2, 2]
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from crslab import _bindings
from crslab._bindings import constants
from crslab.arrays import as_rows

OK: int = constants.IK_SLOT_OK
OUT_OF_LIMITS: int = constants.IK_SLOT_OUT_OF_LIMITS
UNREACHABLE: int = constants.IK_SLOT_UNREACHABLE
SINGULAR_BASE: int = constants.IK_SINGULAR_BASE
SINGULAR_CENTRE: int = constants.IK_SINGULAR_CENTRE
STATUS_TEXT = {OK: "ok", OUT_OF_LIMITS: "outside the joint limits", UNREACHABLE: "out of reach"}
RRR_SLOTS = ("front, q3 >= 0", "front, q3 <= 0", "back, q3 >= 0", "back, q3 <= 0")
PLANAR3R_SLOTS = ("q2 >= 0", "q2 <= 0")


@dataclass(frozen=True)
class Solutions:
    """Every closed-form solution of a batch of targets; see the module docstring."""

    q: np.ndarray
    status: np.ndarray
    singular: np.ndarray
    slot_names: tuple[str, ...]

    @property
    def valid(self) -> np.ndarray:
        """True per slot for an exact solution inside the limits."""
        return self.status == OK


def _limit(values: object) -> np.ndarray | None:
    if values is None:
        return None
    arr = np.ascontiguousarray(values, dtype=np.float64)
    if arr.shape != (3,):
        raise ValueError(f"limits need 3 values, got shape {arr.shape}")
    return arr


def _positive(values: object, count: int, name: str) -> np.ndarray:
    arr = np.ascontiguousarray(values, dtype=np.float64)
    if arr.shape != (count,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be {count} finite numbers, got {values!r}")
    return arr


def _solve(batch: Callable[..., None], params: np.ndarray, src: np.ndarray, lower: object, upper: object,
           slots: tuple[str, ...]) -> Solutions:
    """Every target row of ``src`` (``(..., 3)``) through one of the C core's closed-form batch
    solvers (``params``, the limits, the targets in; each slot's joint angles, status and the
    singular flag out)."""
    lo, hi = _limit(lower), _limit(upper)
    lead = src.shape[:-1]
    q = np.empty(lead + (len(slots), 3))
    status = np.empty(lead + (len(slots),), dtype=np.int32)
    singular = np.empty(lead, dtype=np.int32)
    batch(params, lo, hi, src, q, status, singular, src.size // 3)
    return Solutions(q, status, singular, slots)


def rrr_ik(dims: object, xyz: object, lower: object = None, upper: object = None) -> Solutions:
    """All four IK solutions of the spatial RRR arm for targets ``xyz`` ``(..., 3)``.

    ``dims = (d1, a1, a2, a3)``: the standard DH table is ``(a1, pi/2, d1, q1), (a2, 0, 0, q2),
    (a3, 0, 0, q3)``. Slots: :data:`RRR_SLOTS`. ``singular`` carries :data:`SINGULAR_BASE` on the
    base axis (q1 free, 0 is used) and :data:`SINGULAR_CENTRE` at the shoulder with a2 = a3
    (q2 free, 0 is used).

    >>> sol = rrr_ik((0.0, 10.0, 5.0, 5.0), [0.0, 0.0, 3.0])           # on the base axis
    >>> int(sol.singular) == SINGULAR_BASE, sol.status.tolist()
    (True, [2, 2, 2, 2])
    """
    d = _positive(dims, 4, "dims (d1, a1, a2, a3)")
    if not (d[2] > 0 and d[3] > 0):
        raise ValueError("rrr_ik needs a2 > 0 and a3 > 0")
    return _solve(_bindings.rrr_ik, d, as_rows(xyz, 3, "xyz"), lower, upper, RRR_SLOTS)


def planar3r_ik(links: object, target: object, lower: object = None, upper: object = None) -> Solutions:
    """Both IK solutions of the planar 3R arm for targets ``(x, y, phi_rad)`` ``(..., 3)``.

    ``links = (a1, a2, a3)``; ``phi = q1 + q2 + q3`` is the end link's heading. Slots:
    :data:`PLANAR3R_SLOTS`. ``singular`` carries :data:`SINGULAR_CENTRE` when the wrist point is
    on joint 1 with a1 = a2 (q1 free, 0 is used).

    >>> sol = planar3r_ik((1.0, 1.0, 0.5), [1.0, 1.5, np.pi / 2])
    >>> np.degrees(sol.q).round(6) + 0.0
    array([[  0.,  90.,   0.],
           [ 90., -90.,  90.]])
    """
    a = _positive(links, 3, "links (a1, a2, a3)")
    if not (a[0] > 0 and a[1] > 0):
        raise ValueError("planar3r_ik needs a1 > 0 and a2 > 0")
    return _solve(_bindings.planar3r_ik, a, as_rows(target, 3, "target"), lower, upper, PLANAR3R_SLOTS)
