"""Cartesian waypoint files turned into joint-space trajectories through a robot's IK.

The file format (CSV, for the CRS arm whose length unit is the inch)::

    # a square in front of the arm; lines starting with # and blank lines are ignored
    x_in, y_in, z_in, t_s
    10, 0, 20, 0
    12, -3, 16, 2.0
    12,  3, 16, 3.5
    10, 0, 20,

- The first other line is the header. ``x_in, y_in, z_in`` (the position of the end effector in
  the robot's length unit, inches for the CRS arm) are required; at most one timing column may
  follow:
- ``t_s``: the time (s) at which the arm is at that point, counted from the first row (whose
  ``t_s`` is 0 or empty). Times must increase; a repeated point with a later time is a pause.
- ``speed_in_s``: the average speed (in/s) along the straight line from the previous point to this
  one, which sets that segment's duration; ignored on the first row.
- An empty timing cell, or no timing column, means "as fast as the joint limits allow" (the
  slowest joint's minimum time for the profile, see :func:`crslab.traj.profiles.min_duration`).

Each point becomes joint angles through the robot's IK with the chosen elbow; the arm moves
between consecutive points rest to rest along a synchronized joint-space profile. A point that is
out of reach or outside the joint limits (for the CRS arm the framework's safety envelope), a
timing too fast for the limits, and a move that leaves the limits between points are errors that
name the file and the line.

>>> import io
>>> from crslab import crs
>>> pts = read_waypoints(io.StringIO("x_in,y_in,z_in\\n10,0,20\\n12,0,16\\n"), name="pts.csv")
>>> plan = plan_waypoints(pts, "crs", profile="li", vmax_rad_s=1.0)
>>> plan.trajectory.n_joints, len(plan.trajectory.duration_s)
(3, 1)
>>> np.round(crs.fk(plan.trajectory.waypoints), 9) + 0.0         # the joint path's ends, by FK
array([[10.,  0., 20.],
       [12.,  0., 16.]])
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from crslab.framework_facts import TICKS_PER_S
from crslab.traj.joint_space import ARMS, ArmForWaypoints
from crslab.traj.profiles import Trajectory, TrajectoryError, plan_path

CHECK_RATE_HZ = TICKS_PER_S
"""Between waypoints the joint limits are checked at this rate (the lab's tick rate)."""


class WaypointError(ValueError):
    """A waypoint file that cannot be read or planned. The message starts with the file name and
    the line; ``line`` holds that 1-based line number (None for the file as a whole)."""

    def __init__(self, message: str, line: int | None = None) -> None:
        super().__init__(message)
        self.line = line


@dataclass(frozen=True)
class Waypoints:
    """A parsed waypoint file: ``xyz`` (n, 3) in ``length_unit``; ``t_s`` or ``speed`` (n,),
    NaN where the cell is empty, or None without that column; ``lines`` the file line of each
    row, for messages."""

    name: str
    length_unit: str
    xyz: np.ndarray
    lines: list[int]
    t_s: np.ndarray | None = None
    speed: np.ndarray | None = None


@dataclass(frozen=True)
class WaypointPlan:
    """The joint-space trajectory through a waypoint file and where each row is reached."""

    waypoints: Waypoints
    arm: ArmForWaypoints
    trajectory: Trajectory
    q_rad: np.ndarray
    """joint angles at each row, (n, n_joints)"""
    arrival_s: np.ndarray
    """when the arm comes to rest at each row (s)"""


def _where(name: str, line: int | None) -> str:
    return f"{name} line {line}" if line is not None else name


def read_waypoints(source: str | Path | io.TextIOBase, length_unit: str = "in",
                   name: str | None = None) -> Waypoints:
    """Parse a waypoint file (a path or an open text stream); see the module docstring.

    >>> pts = read_waypoints(io.StringIO("# demo\\nx_in,y_in,z_in,speed_in_s\\n10,0,20,\\n12,0,16,2\\n"))
    >>> pts.xyz.tolist(), pts.speed.tolist()[1], pts.lines
    ([[10.0, 0.0, 20.0], [12.0, 0.0, 16.0]], 2.0, [3, 4])
    """
    if isinstance(source, (str, Path)):
        name = name or str(source)
        try:
            text = Path(source).read_text(encoding="utf-8")
        except FileNotFoundError:
            raise WaypointError(f"{name}: no such file") from None
        except (OSError, UnicodeDecodeError) as exc:
            raise WaypointError(f"{name}: cannot read it ({exc})") from None
    else:
        name = name or "<waypoints>"
        text = source.read()

    xyz_cols = [f"{axis}_{length_unit}" for axis in "xyz"]
    speed_col = f"speed_{length_unit}_s"
    header: list[str] | None = None
    rows: list[list[float]] = []
    lines: list[int] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        stripped = raw.strip()
        if not stripped or stripped.startswith("#"):
            continue
        cells = [c.strip() for c in stripped.split(",")]
        if header is None:
            header = cells
            unknown = [c for c in cells if c not in (*xyz_cols, "t_s", speed_col)]
            missing = [c for c in xyz_cols if c not in cells]
            if unknown or missing or len(set(cells)) != len(cells):
                raise WaypointError(
                    f"{_where(name, number)}: the header must name the columns {', '.join(xyz_cols)} "
                    f"(positions in {length_unit}), optionally with t_s or {speed_col}; got {stripped!r}",
                    number)
            if "t_s" in cells and speed_col in cells:
                raise WaypointError(f"{_where(name, number)}: give t_s or {speed_col}, not both", number)
            continue
        if len(cells) != len(header):
            raise WaypointError(f"{_where(name, number)}: {len(cells)} values for the "
                                f"{len(header)} columns {', '.join(header)}", number)
        values = []
        for column, cell in zip(header, cells):
            if cell == "" and column not in xyz_cols:
                values.append(math.nan)
                continue
            try:
                value = float(cell)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise WaypointError(f"{_where(name, number)}: {column} = {cell!r} is not a number", number)
            values.append(value)
        rows.append(values)
        lines.append(number)
    if header is None:
        raise WaypointError(f"{name}: empty (no header line {', '.join(xyz_cols)})")
    if len(rows) < 2:
        raise WaypointError(f"{name}: needs at least two waypoints, found {len(rows)}")
    table = np.array(rows)
    col = {c: i for i, c in enumerate(header)}
    xyz = table[:, [col[c] for c in xyz_cols]]
    t_s = table[:, col["t_s"]] if "t_s" in col else None
    speed = table[:, col[speed_col]] if speed_col in col else None
    return Waypoints(name, length_unit, xyz, lines, t_s, speed)


def _segment_error(pts: Waypoints, i: int, exc: TrajectoryError) -> WaypointError:
    """A planning failure of segment i (0-based: from row i to row i + 1), as a WaypointError."""
    message = str(exc).removeprefix(f"segment {exc.segment + 1}: " if exc.segment is not None else "")
    line = pts.lines[i + 1]
    return WaypointError(f"{_where(pts.name, line)}: reaching this row from line {pts.lines[i]}: "
                         f"{message}", line)


def _durations(pts: Waypoints, profile: str, q: np.ndarray, vmax: object, amax: object) -> np.ndarray:
    """Each segment's duration (s), NaN for "as fast as the limits allow"."""
    n_seg = q.shape[0] - 1
    out = np.full(n_seg, np.nan)
    if pts.speed is not None:
        for i in range(n_seg):
            v = pts.speed[i + 1]
            if math.isnan(v):
                continue
            if v <= 0:
                raise WaypointError(f"{_where(pts.name, pts.lines[i + 1])}: speed "
                                    f"{v:g} {pts.length_unit}/s must be positive", pts.lines[i + 1])
            out[i] = float(np.linalg.norm(pts.xyz[i + 1] - pts.xyz[i])) / v
    if pts.t_s is None:
        return out
    # absolute times: a segment lasts from when the arm got to the previous row (its own time, or
    # as fast as the limits allowed when that cell is empty) to the time asked for this row
    first = pts.t_s[0]
    if not (math.isnan(first) or first == 0.0):
        raise WaypointError(f"{_where(pts.name, pts.lines[0])}: the first row's t_s must be 0 "
                            f"(or empty), got {first:g}", pts.lines[0])
    arrived, last_given = 0.0, (0.0, pts.lines[0])
    for i in range(n_seg):
        target, line = pts.t_s[i + 1], pts.lines[i + 1]
        if math.isnan(target):
            try:
                out[i] = plan_path(profile, q[i:i + 2], None, vmax, amax).duration_s[0]
            except TrajectoryError as exc:
                raise _segment_error(pts, i, exc) from None
            arrived += out[i]
            continue
        if target <= last_given[0]:
            raise WaypointError(f"{_where(pts.name, line)}: t_s = {target:g} s does not come after the "
                                f"{last_given[0]:g} s of line {last_given[1]}", line)
        if target <= arrived:
            raise WaypointError(f"{_where(pts.name, line)}: t_s = {target:g} s, but the arm only gets to "
                                f"line {pts.lines[i]} at {arrived:.6g} s (as fast as the limits allow)",
                                line)
        out[i] = target - arrived
        arrived, last_given = target, (target, line)
    return out


def plan_waypoints(pts: Waypoints, arm: str | ArmForWaypoints, profile: str = "li", elbow: str = "up",
                   vmax_rad_s: object = 1.0, amax_rad_s2: object = None) -> WaypointPlan:
    """Plan rest-to-rest joint moves through every row of ``pts`` for ``arm`` (a name in
    :data:`crslab.traj.joint_space.ARMS` or an :class:`ArmForWaypoints`).

    ``vmax_rad_s`` and ``amax_rad_s2`` are the joint limits (one for all or one per joint;
    None for none): rows without a time go as fast as they allow, rows with one must respect
    them. Raises :class:`WaypointError` naming the file and line of the first problem.
    """
    if isinstance(arm, str):
        if arm not in ARMS:
            raise WaypointError(f"unknown robot {arm!r}; choose one of {', '.join(ARMS)}")
        arm = ARMS[arm]
    if pts.length_unit != arm.length_unit:
        raise WaypointError(f"{pts.name}: positions are in {pts.length_unit} but the {arm.name} arm "
                            f"works in {arm.length_unit}")
    q, problems = arm.solve(pts.xyz, elbow)
    for i, problem in enumerate(problems):
        if problem is not None:
            x, y, z = pts.xyz[i]
            raise WaypointError(f"{_where(pts.name, pts.lines[i])}: waypoint ({x:g}, {y:g}, {z:g}) "
                                f"{pts.length_unit} is {problem}", pts.lines[i])
    bad = np.flatnonzero(arm.outside(q))
    if bad.size:
        i = int(bad[0])
        x, y, z = pts.xyz[i]
        raise WaypointError(f"{_where(pts.name, pts.lines[i])}: waypoint ({x:g}, {y:g}, {z:g}) "
                            f"{pts.length_unit} with the elbow {elbow} is outside the {arm.name} arm's "
                            f"{arm.limits_name}: {arm.why_outside(q[i])}", pts.lines[i])

    durations = _durations(pts, profile, q, vmax_rad_s, amax_rad_s2)
    try:
        trajectory = plan_path(profile, q, durations, vmax_rad_s, amax_rad_s2)
    except TrajectoryError as exc:
        raise _segment_error(pts, exc.segment or 0, exc) from None
    arrival = np.append(trajectory.start_s, trajectory.end_s)
    _check_between(pts, arm, trajectory, arrival)
    return WaypointPlan(pts, arm, trajectory, q, arrival)


def _check_between(pts: Waypoints, arm: ArmForWaypoints, trajectory: Trajectory,
                   arrival: np.ndarray) -> None:
    """The joint limits hold at every tick, not only at the waypoints."""
    t, samples = trajectory.sample(CHECK_RATE_HZ)
    bad = np.flatnonzero(arm.outside(samples.q))
    if not bad.size:
        return
    k = int(bad[0])
    i = int(np.clip(np.searchsorted(arrival, t[k], side="right"), 1, len(arrival) - 1))
    raise WaypointError(
        f"{_where(pts.name, pts.lines[i])}: the move from line {pts.lines[i - 1]} to this row leaves "
        f"the {arm.name} arm's {arm.limits_name} at t = {t[k]:.3f} s: {arm.why_outside(samples.q[k])}",
        pts.lines[i])
