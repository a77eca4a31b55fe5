"""Joint trajectory profiles over the C core (``csrc/kin/traj_profiles.h``), numpy in and out.

Four point-to-point profiles, each rest to rest, named as on the command line:

``li``
    Huaizhong Li's sinusoidal jerk: an acceleration phase whose acceleration is
    ``(A/2)(1 - cos(2 pi t/Ta))`` and its mirror image, so the jerk is continuous and zero at both
    ends. Without a binding speed limit ``Ta = T/2`` and ``A = 8L/T^2`` (peak velocity ``2L/T``);
    under a speed limit it cruises at the limit between the two phases.
``quintic``
    the minimum-jerk polynomial: zero velocity and acceleration at both ends.
``cubic``
    the third-order polynomial of the course's Lab 2: zero velocity at both ends.
``trapezoid``
    constant acceleration, cruise, constant deceleration (a third of the time each, unless the
    speed limit is lower than that cruise speed).

A :class:`Trajectory` is a chain of such moves for several joints, synchronized so every joint of
a segment starts and stops together (the segment lasts as long as its slowest joint needs).
Positions are in the joints' unit (rad for the course's revolute joints), times in seconds.

>>> move = plan_move("li", [0.0, 1.0], [2.0, 0.5], duration_s=4.0)
>>> s = move.evaluate([0.0, 1.0, 2.0, 4.0])
>>> s.q[:, 0].round(6).tolist()        # rest, 1/4 - 1/pi^2 at T/4, halfway at T/2, arrived
[0.0, 0.148679, 1.0, 2.0]
>>> s.qd[2].tolist()                           # peak velocity 2L/T for each joint
[1.0, -0.25]
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from crslab import _bindings
from crslab._bindings import constants
from crslab.framework_facts import TICKS_PER_S

PROFILES: dict[str, int] = {
    "li": constants.TRAJ_LI,
    "quintic": constants.TRAJ_QUINTIC,
    "cubic": constants.TRAJ_CUBIC,
    "trapezoid": constants.TRAJ_TRAPEZOID,
}
"""Profile names (as ``crslab traj --profile`` takes them) and their ``traj_kind`` values."""


class TrajectoryError(ValueError):
    """A move that cannot be planned. ``segment`` and ``joint`` (0-based) say where, when known."""

    def __init__(self, message: str, segment: int | None = None, joint: int | None = None) -> None:
        super().__init__(message)
        self.segment = segment
        self.joint = joint


class Samples(NamedTuple):
    """A trajectory at some times: arrays of shape ``(n_times, n_joints)``."""

    q: np.ndarray
    """position (rad)"""
    qd: np.ndarray
    """velocity (rad/s)"""
    qdd: np.ndarray
    """acceleration (rad/s^2)"""
    jerk: np.ndarray
    """jerk (rad/s^3)"""


def _kind(profile: str) -> int:
    try:
        return PROFILES[profile]
    except KeyError:
        raise ValueError(f"unknown profile {profile!r}; choose one of {', '.join(PROFILES)}") from None


def _limits(limit: object, n_joints: int, name: str) -> np.ndarray:
    """One limit per joint; ``None`` (or <= 0, or inf) means no limit, stored as 0."""
    if limit is None:
        return np.zeros(n_joints)
    arr = np.broadcast_to(np.asarray(limit, dtype=np.float64), (n_joints,))
    if np.isnan(arr).any():
        raise ValueError(f"{name} must not be NaN")
    return np.ascontiguousarray(np.where(np.isfinite(arr) & (arr > 0), arr, 0.0))


def min_duration(profile: str, q0: object, qf: object, vmax: object = None,
                 amax: object = None) -> np.ndarray:
    """The shortest duration (s) of each joint's move within its speed and acceleration limits.

    With both limits, ``li`` and ``trapezoid`` cruise at ``vmax`` when the move is long. With only
    a speed limit they have no shortest duration (any T > L/vmax works by cruising, with ever
    harder ramps), so this is where their unlimited shape just reaches ``vmax``.

    >>> min_duration("li", [0.0, 0.0], [1.0, -3.0], vmax=2.0).tolist()    # 2L/vmax
    [1.0, 3.0]
    >>> min_duration("cubic", 0.0, 1.0, amax=6.0).tolist()                 # sqrt(6L/amax)
    [1.0]
    """
    kind = _kind(profile)
    a = np.atleast_1d(np.asarray(q0, dtype=np.float64))
    b = np.atleast_1d(np.asarray(qf, dtype=np.float64))
    v, acc = _limits(vmax, a.size, "vmax"), _limits(amax, a.size, "amax")
    out = np.empty(a.size)
    for j in range(a.size):  # one call per joint: planning is not the hot path
        status, out[j] = _bindings.traj_min_duration(kind, a[j], b[j], v[j], acc[j])
        if status != constants.TRAJ_OK:
            raise TrajectoryError(f"joint {j + 1}: positions must be finite ({a[j]} to {b[j]})", joint=j)
    return out


class Trajectory:
    """Rest-to-rest moves of ``n_joints`` joints, one segment after another.

    Segment ``i`` starts at ``start_s[i]`` and lasts ``duration_s[i]``; its joints start and stop
    together. ``waypoints`` holds the joint positions at the start and at the end of every
    segment, shape ``(n_segments + 1, n_joints)``; before the first segment the joints rest at
    ``waypoints[0]``, after the last at ``waypoints[-1]``. Build one with :func:`plan_move` or
    :func:`plan_path`.
    """

    def __init__(self, profile: str, segments: object, start_s: np.ndarray, n_joints: int) -> None:
        self.profile = profile
        self.n_joints = n_joints
        self.start_s = start_s
        self._segments = segments  # cdata traj_profile[n_segments * n_joints]
        n_seg = start_s.size
        self.duration_s = np.array([segments[i * n_joints].duration_s for i in range(n_seg)])
        self.waypoints = np.array(
            [[segments[0 * n_joints + j].q0_rad for j in range(n_joints)]]
            + [[segments[i * n_joints + j].qf_rad for j in range(n_joints)] for i in range(n_seg)]
        )

    @property
    def end_s(self) -> float:
        """When the last segment ends (s)."""
        return float(self.start_s[-1] + self.duration_s[-1])

    @property
    def c_segments(self) -> object:
        """The planned ``traj_profile[n_segments * n_joints]`` (:func:`crslab._bindings.traj_segments`)."""
        return self._segments

    def evaluate(self, t_s: object) -> Samples:
        """Position, velocity, acceleration and jerk at each time in ``t_s`` (s), in one C call.

        >>> move = plan_move("cubic", [0.0], [1.0], duration_s=2.0)
        >>> move.evaluate([-1.0, 1.0, 5.0]).q[:, 0].tolist()    # clamped outside [0, T]
        [0.0, 0.5, 1.0]
        """
        t = np.ascontiguousarray(np.atleast_1d(np.asarray(t_s, dtype=np.float64)).ravel())
        out = [np.empty((t.size, self.n_joints)) for _ in range(4)]
        _bindings.traj_evaluate(self._segments, self.start_s, self.n_joints, t, *out)
        return Samples(*out)

    def sample(self, rate_hz: int = TICKS_PER_S) -> tuple[np.ndarray, Samples]:
        """The trajectory at tick ``k`` = ``k / rate_hz`` seconds, from 0 to the first tick at or
        after the end (times from integer ticks, never accumulated).

        >>> t, s = plan_move("li", [0.0], [1.0], duration_s=0.0025).sample()
        >>> t.tolist(), s.q[:, 0].round(6).tolist()
        ([0.0, 0.001, 0.002, 0.003], [0.0, 0.302497, 0.965823, 1.0])
        """
        last_tick = math.ceil(round(self.end_s * rate_hz, 9))
        t = np.arange(last_tick + 1) / rate_hz
        return t, self.evaluate(t)


def _plan_segment(kind: int, segments: object, offset: int, q0: np.ndarray, qf: np.ndarray,
                  duration_s: float, vmax: np.ndarray, amax: np.ndarray, profile: str,
                  exact: bool, segment: int) -> None:
    n = q0.size
    status, failed = _bindings.traj_plan_synchronized(segments, offset, n, kind, q0, qf, duration_s, vmax,
                                                      amax)
    where = f"segment {segment + 1}: " if segment is not None else ""
    if status == constants.TRAJ_BAD_ARGUMENT:
        j = failed
        what = f"joint {j + 1} from {q0[j]} to {qf[j]}" if j < n else f"duration {duration_s}"
        raise TrajectoryError(f"{where}cannot plan {what}: positions must be finite and durations "
                              "finite and >= 0", segment, j if j < n else None)
    if status == constants.TRAJ_TOO_FAST:  # only without limits: a move in no time
        j = failed
        raise TrajectoryError(f"{where}joint {j + 1} cannot move from {q0[j]:.6g} to {qf[j]:.6g} in "
                              f"{duration_s:g} s (give a duration or a speed limit)", segment, j)
    if exact and segments[offset].duration_s != duration_s:  # stretched: some joint cannot
        j = next(j for j in range(n) if _bindings.traj_plan_status(
            kind, q0[j], qf[j], duration_s, vmax[j], amax[j]) != constants.TRAJ_OK)
        limits = [f"{vmax[j]:g} rad/s"] if vmax[j] > 0 else []
        limits += [f"{amax[j]:g} rad/s^2"] if amax[j] > 0 else []
        if profile in ("li", "trapezoid") and amax[j] == 0:  # can cruise at vmax, so any T > L/vmax
            need = f"more than {abs(qf[j] - q0[j]) / vmax[j]:.6g} s"
        else:
            need = f"at least {min_duration(profile, q0[j], qf[j], vmax[j], amax[j])[0]:.6g} s"
        raise TrajectoryError(
            f"{where}{duration_s:.6g} s is too fast for the {profile} profile: joint {j + 1} "
            f"({q0[j]:.6g} to {qf[j]:.6g} rad) needs {need} within {' and '.join(limits)}", segment, j)


def plan_path(profile: str, waypoints: object, durations_s: object = None, vmax: object = None,
              amax: object = None) -> Trajectory:
    """Rest-to-rest moves through joint-space ``waypoints`` (shape ``(n_points, n_joints)``).

    ``durations_s`` gives each segment's duration (``n_points - 1`` values); a NaN entry, or
    ``None`` for all, means "as fast as the limits allow" (the slowest joint's minimum). A given
    duration is kept exactly, and one too short for the limits raises :class:`TrajectoryError`
    naming the segment and the joint. ``vmax`` (rad/s) and ``amax`` (rad/s^2) are per joint or
    one for all; ``None`` is no limit.

    >>> path = plan_path("quintic", [[0.0, 0.0], [1.0, 0.5], [1.0, -0.5]], vmax=1.875)
    >>> path.duration_s.tolist(), path.start_s.tolist()
    ([1.0, 1.0], [0.0, 1.0])
    >>> plan_path("li", [[0.0], [1.0]], durations_s=[0.5], vmax=2.0)
    Traceback (most recent call last):
    ...
    crslab.traj.profiles.TrajectoryError: segment 1: 0.5 s is too fast for the li profile: joint 1 ...
    """
    kind = _kind(profile)
    q = np.ascontiguousarray(np.asarray(waypoints, dtype=np.float64))
    if q.ndim != 2 or q.shape[0] < 2 or q.shape[1] < 1:
        raise ValueError(f"waypoints must have shape (n_points >= 2, n_joints), got {q.shape}")
    n_seg, n = q.shape[0] - 1, q.shape[1]
    if durations_s is None:
        durations = np.full(n_seg, np.nan)
    else:
        durations = np.asarray(durations_s, dtype=np.float64).reshape(-1)
        if durations.size != n_seg:
            raise ValueError(f"durations_s needs {n_seg} values (one per segment), got {durations.size}")
    v, a = _limits(vmax, n, "vmax"), _limits(amax, n, "amax")
    segments = _bindings.traj_segments(n_seg * n)
    start = np.zeros(n_seg)
    for i in range(n_seg):
        given = not math.isnan(durations[i])
        _plan_segment(kind, segments, i * n, np.ascontiguousarray(q[i]), np.ascontiguousarray(q[i + 1]),
                      float(durations[i]) if given else 0.0, v, a, profile, given, i)
        if i + 1 < n_seg:
            start[i + 1] = start[i] + segments[i * n].duration_s
    return Trajectory(profile, segments, start, n)


def plan_move(profile: str, q0: object, qf: object, duration_s: float | None = None, vmax: object = None,
              amax: object = None) -> Trajectory:
    """One synchronized move of every joint from ``q0`` to ``qf``.

    With ``duration_s`` the move takes exactly that long (too short for the limits raises
    :class:`TrajectoryError`); without it, as long as the slowest joint needs within its limits.

    >>> plan_move("trapezoid", [0.0, 0.0], [3.0, 1.0], vmax=1.5).duration_s.tolist()  # 1.5L/vmax
    [3.0]
    """
    a = np.atleast_1d(np.asarray(q0, dtype=np.float64))
    b = np.atleast_1d(np.asarray(qf, dtype=np.float64))
    if a.shape != b.shape or a.ndim != 1:
        raise ValueError(f"q0 and qf must be the same length, got shapes {a.shape} and {b.shape}")
    durations = None if duration_s is None else [duration_s]
    try:
        return plan_path(profile, np.stack([a, b]), durations, vmax, amax)
    except TrajectoryError as exc:
        raise TrajectoryError(str(exc).removeprefix("segment 1: "), None, exc.joint) from None
