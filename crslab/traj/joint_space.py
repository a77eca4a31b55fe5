"""What the waypoint planner needs from each robot: its length unit, closed-form IK with an
elbow choice, and the joint limits a trajectory must respect.

``ARMS`` maps the names ``crslab traj`` takes to :class:`ArmForWaypoints`. The CRS arm plans in
motor angles (what ``lab()`` receives) and its limits are the framework's safety envelope: a
trajectory that leaves it would be overridden by the hold controller on the real board. The
spatial RRR arm of seed 003 plans in its DH joint angles, within the limits of its robot file
(``crslab/robots/rrr.toml``; lengths in that file's unit).

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
from crslab.closed_ik import OK, OUT_OF_LIMITS
from crslab.robots import load


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


def crs_outside_envelope(motor_rad: object) -> np.ndarray:
    """True for each row of motor angles (rad) outside the CRS framework's safety envelope
    (:func:`crslab.crs.outside_envelope`, the C core's own test).

    >>> crs_outside_envelope(np.radians([[0, 0, 0], [0, 90, 0], [130, 0, 0]])).tolist()
    [False, True, True]
    """
    return crs.outside_envelope(np.asarray(motor_rad, dtype=float).reshape(-1, 3))


def crs_why_outside(motor_rad: object) -> str:
    """Which part of the safety envelope a pose (motor angles, rad) violates, in words.

    >>> crs_why_outside(np.radians([0, 90, 0]))
    'th3 DH = 0.00 deg is outside [8.59, 131.78] deg'
    """
    q = np.asarray(motor_rad, dtype=float).reshape(3)
    dh, z = crs.motor_to_dh(q), float(crs.fk(q)[2])
    reasons = []
    if abs(dh[0]) > crs.ENVELOPE_TH1_MAX_RAD:
        reasons.append(f"th1 = {math.degrees(dh[0]):.4g} deg is beyond "
                       f"+-{math.degrees(crs.ENVELOPE_TH1_MAX_RAD):.2f} deg")
    for name, value, (lo, hi) in (("th2", dh[1], crs.ENVELOPE_TH2_RAD), ("th3", dh[2], crs.ENVELOPE_TH3_RAD)):
        if not lo <= value <= hi:
            reasons.append(f"{name} DH = {math.degrees(value) + 0.0:.2f} deg is outside "
                           f"[{math.degrees(lo):.2f}, {math.degrees(hi):.2f}] deg")
    if z < crs.ENVELOPE_Z_MIN_IN:
        reasons.append(f"z = {z:.4g} in is below {crs.ENVELOPE_Z_MIN_IN:g} in")
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


def _rrr_arm() -> ArmForWaypoints:
    """The spatial RRR arm of seed 003, from its robot file (crslab/robots/rrr.toml)."""
    robot = load("rrr")
    lower, upper = robot.chain.lower, robot.chain.upper
    # Of the four closed-form slots the planner uses the two in front (q1 = atan2(y, x)). There
    # q2 raises the arm (alpha1 = +pi/2), so q3 <= 0 puts the elbow above the line from the
    # shoulder to the target: elbow up, as on the CRS arm (whose th3 DH >= 0 means the same,
    # its alpha1 being -pi/2). Seed 003's own formula, q3 = acos(...) >= 0, is elbow down.
    slot = {"up": 1, "down": 0}

    def solve(xyz: np.ndarray, elbow: str) -> tuple[np.ndarray, list[str | None]]:
        if elbow not in slot:
            raise ValueError(f"elbow must be 'up' or 'down', got {elbow!r}")
        sol = robot.closed_ik(np.asarray(xyz, dtype=float).reshape(-1, 3))
        q = sol.q[:, slot[elbow], :]
        status = sol.status[:, slot[elbow]]
        return q, [None if s in (OK, OUT_OF_LIMITS) else "out of reach" for s in status]

    def outside(q: np.ndarray) -> np.ndarray:
        return ~robot.chain.within_limits(q)

    def why_outside(q_row: np.ndarray) -> str:
        reasons = [f"joint {j + 1} = {math.degrees(v):.4g} deg is outside "
                   f"[{math.degrees(lo):.4g}, {math.degrees(hi):.4g}] deg"
                   for j, (v, lo, hi) in enumerate(zip(q_row, lower, upper)) if not lo <= v <= hi]
        return "; ".join(reasons) or "inside the joint limits"

    return ArmForWaypoints(name="rrr", length_unit=robot.length_unit, joint_label="joint",
                           limits_name="joint limits", n_joints=3, solve=solve, outside=outside,
                           why_outside=why_outside)


ARMS: dict[str, ArmForWaypoints] = {"crs": CRS, "rrr": _rrr_arm()}
"""The robots ``crslab traj`` plans for, by name."""
