"""What the waypoint planner needs from each robot: its length unit, closed-form IK with an
elbow choice, and the joint limits a trajectory must respect.

``ARMS`` maps the names ``crslab traj`` takes to :class:`ArmForWaypoints`. The CRS arm plans in
motor angles (what ``lab()`` receives) and its limits are the framework's safety envelope: a
trajectory that leaves it would be overridden by the hold controller on the real board.

>>> q, problems = ARMS["crs"].solve([[10, 0, 20], [0, 0, 31]], "up")
>>> np.degrees(q[0]).round(9) + 0.0, problems
(array([0., 0., 0.]), [None, 'out of reach (farther than 20 in from the shoulder)'])
>>> ARMS["crs"].outside(q[:1]).tolist()        # motor zero is inside the envelope
[False]
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from crslab import crs

# The CRS framework's safety envelope (crs-facts section 2, item 4), on the angles it computes
# from the encoders. The same numbers drive the simulated framework in csrc/sim/framework.c
# (crs_outside_envelope); tests/test_traj_waypoints.py checks that the two agree.
ENVELOPE_TH1_MAX_RAD = 0.6667 * math.pi
ENVELOPE_TH2_RAD = (-2.3, 0.15)
ENVELOPE_TH3_RAD = (0.15, 2.3)
ENVELOPE_Z_MIN_IN = 4.0


@dataclass(frozen=True)
class ArmForWaypoints:
    """A robot as the waypoint planner sees it.

    ``solve(xyz, elbow)`` returns joint angles (rad), shape ``(n, n_joints)``, and per row
    ``None`` or why the row has no usable solution. ``outside(q)`` flags rows outside the joint
    limits (called ``limits_name`` in messages) and ``why_outside(q_row)`` says which limit, in
    words. ``joint_label`` says what the joint angles are (the CRS arm's are motor angles).
    """

    name: str
    length_unit: str
    joint_label: str
    limits_name: str
    n_joints: int
    solve: Callable[[np.ndarray, str], tuple[np.ndarray, list[str | None]]]
    outside: Callable[[np.ndarray], np.ndarray]
    why_outside: Callable[[np.ndarray], str]


def _crs_solve(xyz_in: np.ndarray, elbow: str) -> tuple[np.ndarray, list[str | None]]:
    q, status = crs.ik_with_status(np.asarray(xyz_in, dtype=float).reshape(-1, 3), elbow)
    return q, [None if s == crs.IK_OK else crs.IK_STATUS_TEXT[int(s)] for s in status]


def _crs_envelope_terms(motor_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    q = np.asarray(motor_rad, dtype=float).reshape(-1, 3)
    return crs.motor_to_dh(q), crs.fk(q)[:, 2]


def crs_outside_envelope(motor_rad: object) -> np.ndarray:
    """True for each row of motor angles (rad) outside the CRS framework's safety envelope.

    >>> crs_outside_envelope(np.radians([[0, 0, 0], [0, 90, 0], [130, 0, 0]])).tolist()
    [False, True, True]
    """
    dh, z = _crs_envelope_terms(np.asarray(motor_rad))
    return ((np.abs(dh[:, 0]) > ENVELOPE_TH1_MAX_RAD)
            | (dh[:, 1] < ENVELOPE_TH2_RAD[0]) | (dh[:, 1] > ENVELOPE_TH2_RAD[1])
            | (dh[:, 2] < ENVELOPE_TH3_RAD[0]) | (dh[:, 2] > ENVELOPE_TH3_RAD[1])
            | (z < ENVELOPE_Z_MIN_IN))


def crs_why_outside(motor_rad: object) -> str:
    """Which part of the safety envelope a pose (motor angles, rad) violates, in words.

    >>> crs_why_outside(np.radians([0, 90, 0]))
    'th3 DH = 0 deg is outside [8.59, 131.78] deg'
    """
    dh, z = _crs_envelope_terms(np.asarray(motor_rad))
    th1, th2, th3 = np.degrees(dh[0]) + 0.0
    reasons = []
    if abs(dh[0, 0]) > ENVELOPE_TH1_MAX_RAD:
        reasons.append(f"th1 = {th1:.4g} deg is beyond +-{math.degrees(ENVELOPE_TH1_MAX_RAD):.2f} deg")
    for name, value, (lo, hi) in (("th2", th2, ENVELOPE_TH2_RAD), ("th3", th3, ENVELOPE_TH3_RAD)):
        if not lo <= math.radians(value) <= hi:
            reasons.append(f"{name} DH = {value:.4g} deg is outside "
                           f"[{math.degrees(lo):.2f}, {math.degrees(hi):.2f}] deg")
    if z[0] < ENVELOPE_Z_MIN_IN:
        reasons.append(f"z = {z[0]:.4g} in is below {ENVELOPE_Z_MIN_IN:g} in")
    return "; ".join(reasons) or "inside the envelope"


CRS = ArmForWaypoints(
    name="crs",
    length_unit="in",
    joint_label="motor angle",
    limits_name="safety envelope",
    n_joints=3,
    solve=_crs_solve,
    outside=crs_outside_envelope,
    why_outside=crs_why_outside,
)

ARMS: dict[str, ArmForWaypoints] = {"crs": CRS}
"""The robots ``crslab traj`` plans for, by name."""
