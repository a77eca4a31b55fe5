"""A push at the end effector (``push``): a force in newtons at the point where the course's forward
kinematics puts x, y, z, as the course's Lab 4 simulation pushes the arm in place of a hand.

The force is given in the world frame (the arm's base frame, DH frame 0) or in a frame N rotated
as the Lab 4 handout rotates its stiffness frame, ``R = Rz(thz) Rx(thx) Ry(thy)``: a force ``F``
given in N is ``R F`` in the world. It is constant, or a square wave: ``+F`` for the first half of
each ``period``, ``-F`` for the second. The board works out each tick's force in C from the tick
number (csrc/plant/push.h), so the transcript is the same however a run's ticks are chunked. A
later ``push`` replaces the one before; ``until`` ends it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from crslab.framework_facts import TICKS_PER_S
from crslab.scenario.event import LONGEST_S, Event, RandomFaults, until_tick
from crslab.scenario.file_table import MAX_PUSH_N
from crslab.toml_file import Table

FRAME_ANGLES = ("thz", "thx", "thy")
"""The angles of a push's frame, in the order the rotation applies them: R = Rz Rx Ry."""


def lab4_frame_matrix(thz_rad: float, thx_rad: float, thy_rad: float) -> np.ndarray:
    """The Lab 4 handout's rotation of a frame N, ``R = Rz(thz) Rx(thx) Ry(thy)``: its columns are
    N's x, y, z axes in the world, and a vector given in N is ``R v`` in the world.

    >>> (lab4_frame_matrix(math.pi / 2, 0.0, 0.0) @ [1.0, 0.0, 0.0]).round(12) + 0.0
    array([0., 1., 0.])
    """
    cz, sz = math.cos(thz_rad), math.sin(thz_rad)
    cx, sx = math.cos(thx_rad), math.sin(thx_rad)
    cy, sy = math.cos(thy_rad), math.sin(thy_rad)
    rz = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
    ry = np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])
    return rz @ rx @ ry


def _vector(values: object) -> str:
    """``(a, b, c)`` with at most three decimals (``-0`` shown as ``0``)."""
    return "(" + ", ".join(f"{round(float(v), 3) + 0.0:g}" for v in values) + ")"  # type: ignore[attr-defined]


@dataclass(frozen=True)
class Push(Event):
    """From now on, push the end effector with ``force_n`` (world frame, N): constant when
    ``half_period_ticks`` is 0, else a square wave that flips sign every ``half_period_ticks``
    counted from this tick. ``given_n`` and ``frame_rad`` (thz, thx, thy; None: the world) are the
    force as the scenario gave it. ``ends``: the push stops instead.

    >>> Push(tick=6000, force_n=(5.0, 5.0, 5.0), half_period_ticks=1000, given_n=(5.0, 5.0, 5.0)).describe()
    'push (5, 5, 5) N at the end effector (world frame), square wave: sign flips every 1 s'
    >>> Push(tick=0, force_n=(-4.33, 2.5, 0.0), given_n=(0.0, 5.0, 0.0),
    ...      frame_rad=(math.pi / 3, 0.0, 0.0)).describe()
    'push (0, 5, 0) N in frame N (thz 60, thx 0, thy 0 deg) = (-4.33, 2.5, 0) N world at the end effector'
    """

    force_n: tuple[float, float, float]
    half_period_ticks: int = 0
    given_n: tuple[float, float, float] = (0.0, 0.0, 0.0)
    frame_rad: tuple[float, float, float] | None = None
    ends: bool = False
    kinds = ("push",)

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "force_n", "frame_rad", "frame_deg", "period", "until"})
        if "force_n" not in r.table:
            raise r.fail("force_n", "missing (the force, N: a list of three numbers)")
        given = r.triple("force_n")
        if np.any(np.abs(given) > MAX_PUSH_N):
            raise r.fail("force_n", f"each component must be within +-{MAX_PUSH_N:g} N, got {given.tolist()}")
        frame = _frame(r)
        world = given if frame is None else lab4_frame_matrix(*frame) @ given
        half = 0
        if "period" in r.table:
            period_s = r.number("period", minimum=0.0, maximum=LONGEST_S)
            half_ms = period_s * 500.0
            half = int(round(half_ms))
            if half < 1 or abs(half_ms - half) > 1e-6:
                raise r.fail("period", f"half of it must be a whole number of ms (at least 1), "
                                       f"got {period_s!r} s")
        until = until_tick(r, at)
        out: list[Event] = [cls(tick=at, force_n=_triple(world), half_period_ticks=half,
                                given_n=_triple(given), frame_rad=frame, line=line)]
        if until is not None:
            out.append(cls(tick=until, force_n=(0.0, 0.0, 0.0), ends=True, line=line))
        return out

    def describe(self) -> str:
        if self.ends:
            return "push ends"
        if self.frame_rad is None:
            where = f"{_vector(self.given_n)} N at the end effector (world frame)"
        else:
            angles = ", ".join(f"{name} {math.degrees(a) + 0.0:.4g}"
                               for name, a in zip(FRAME_ANGLES, self.frame_rad, strict=True))
            where = (f"{_vector(self.given_n)} N in frame N ({angles} deg) = {_vector(self.force_n)} N world"
                     " at the end effector")
        if self.half_period_ticks:
            where += f", square wave: sign flips every {self.half_period_ticks / TICKS_PER_S:g} s"
        return "push " + where


def _triple(v: np.ndarray) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))


def _frame(r: Table) -> tuple[float, float, float] | None:
    """The push's frame: ``frame_rad`` or ``frame_deg``, an inline table of thz, thx, thy (each
    optional, default 0); None when neither is given (the world frame)."""
    given = [k for k in ("frame_rad", "frame_deg") if k in r.table]
    if not given:
        return None
    if len(given) == 2:
        raise r.fail("frame_deg", "give frame_rad or frame_deg, not both")
    key = given[0]
    table = r.table[key]
    if not isinstance(table, dict):
        raise r.fail(key, f"must be a table of {', '.join(FRAME_ANGLES)}, e.g. {{thz = 60}}, got {table!r}")
    angles = []
    for name in FRAME_ANGLES:
        value = table.get(name, 0.0)
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise r.fail(key, f"{name} must be a number, got {value!r}")
        angles.append(math.radians(value) if key == "frame_deg" else float(value))
    unknown = sorted(set(table) - set(FRAME_ANGLES))
    if unknown:
        raise r.fail(key, f"unknown angle {unknown[0]!r} (the frame's angles: {', '.join(FRAME_ANGLES)})")
    return (angles[0], angles[1], angles[2])
