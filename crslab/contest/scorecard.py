"""The final project's scorecard: what one run of a lab did in the contest world, task by task.

:func:`score` is pure: it reads a run's scope log (one row per tick; the world's signals of
:mod:`crslab.scopes.signals`: ``peg_tip``, ``egg_force``, ``scale_g``, ``egg_broken``,
``obstacle_force``, ``groove_side_force``) and the world's layout (where each fixture is, the
contest's rules), and returns a :class:`Scorecard`. Nothing here runs a lab.

How each task is scored (docs/contest.md says the same for students):

- **peg**: the peg's depth is how far its tip is below the hole block's top while the tip is
  within the hole's radius of the hole's axis (0 elsewhere); the task is done when the depth
  stays at least ``peg_min_depth_m`` for ``peg_hold_s`` without a break.
- **obstacle**: touched when the contact force between the arm and the obstacle ever exceeds
  :data:`TOUCH_N`; passed over when the peg's tip is ever above the obstacle's top inside its
  footprint; done when passed over and never touched.
- **groove**: the tip is inside the groove while it is within half the groove's width of the Z's
  centre line and below the plate's top (at most the groove's depth, plus :data:`DEPTH_SLACK_M`).
  From the first row inside, the stay lasts while the tip is inside; the share is how much of
  the Z's length (along its centre line) the tip covered in that stay. Leaving before the last
  corner's end (farther than half a width from the exit) is where it left. Done when the share is
  at least ``groove_min_share``.
- **egg**: the scale's reading in grams; the longest unbroken time within the band
  ``band_g`` (inclusive); done when that is at least ``hold_s`` and the egg is not broken.
- **time**: from the first motion (the tip :data:`MOTION_M` from where it was on the first row)
  to the moment the last task was complete; only when all four are done.

>>> import numpy as np
>>> longest_run(np.array([1, 1, 0, 1, 1, 1, 0], bool))
(3, 3)
>>> longest_run(np.zeros(4, bool))
(0, -1)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from crslab.framework_facts import TICKS_PER_S
from crslab.world.fixtures import ContestRules
from crslab.world.world_facts import TOUCH_N, groove_nearest, peg_depths

MOTION_M = 0.005
"""The first motion: the peg's tip this far (m) from where it was on the log's first row."""
DEPTH_SLACK_M = 0.005
"""Below the groove's floor by this much (m) still counts as inside (the contact's penetration)."""


class ScorecardError(ValueError):
    """The scope log cannot be scored (a signal missing, no rows); its str is one line."""


@dataclass(frozen=True)
class Peg:
    done: bool
    depth_m: float          # deepest the tip went below the hole's top, in the hole
    held_s: float           # longest stay at least peg_min_depth_m deep
    done_at_s: float | None
    note: str = ""          # why it cannot be scored (no hole in the world)


@dataclass(frozen=True)
class Obstacle:
    done: bool
    touched: bool
    max_force_n: float
    touched_at_s: float | None
    passed_over: bool
    over_at: tuple[float, float, float] | None   # where the tip first was above it (m)
    done_at_s: float | None
    note: str = ""


@dataclass(frozen=True)
class Groove:
    done: bool
    share: float            # of the Z's centre line covered in the first stay inside (0..1)
    max_side_force_n: float
    left_at: tuple[float, float] | None   # where the tip left before the exit (m), None if it did not
    entered_at_s: float | None
    done_at_s: float | None
    note: str = ""
    reached_exit: bool = False   # the stay reached the exit's last half width


@dataclass(frozen=True)
class Egg:
    done: bool
    peak_g: float
    in_band_s: float        # longest unbroken time within the band
    broken: bool
    broken_at_s: float | None
    done_at_s: float | None
    note: str = ""


@dataclass(frozen=True)
class Scorecard:
    """A run's four tasks and its time (None unless all four are done)."""

    peg: Peg
    obstacle: Obstacle
    groove: Groove
    egg: Egg
    time_s: float | None
    first_motion_s: float | None
    rules: ContestRules

    TASKS = ("peg", "obstacle", "groove", "egg")

    @property
    def done(self) -> int:
        """How many of the four tasks are done."""
        return sum(getattr(self, t).done for t in self.TASKS)

    def as_dict(self) -> dict:
        """The JSON shape of docs/contest.md."""
        def r(v: float | None, nd: int = 4) -> float | None:
            return None if v is None else round(float(v), nd)
        p, o, g, e = self.peg, self.obstacle, self.groove, self.egg
        return {
            "tasks": {
                "peg": {"done": p.done, "depth_m": r(p.depth_m), "held_s": r(p.held_s, 3)},
                "obstacle": {"done": o.done, "touched": o.touched, "max_force_n": r(o.max_force_n, 3),
                             "passed_over": o.passed_over},
                "groove": {"done": g.done, "share": r(g.share, 3),
                           "max_side_force_n": r(g.max_side_force_n, 3),
                           "left_at": None if g.left_at is None else [r(v) for v in g.left_at]},
                "egg": {"done": e.done, "peak_g": r(e.peak_g, 1), "in_band_s": r(e.in_band_s, 3),
                        "broken": e.broken},
            },
            "time_s": r(self.time_s, 3),
        }

    def lines(self) -> list[str]:
        """One line per task with its evidence, then the time."""
        ru = self.rules
        p, o, g, e = self.peg, self.obstacle, self.groove, self.egg

        def mark(done: bool) -> str:
            return "done" if done else "FAIL"

        def at(t: float | None) -> str:
            return "" if t is None else f" at t = {t:.2f} s"

        out = []
        need = f"(needs {1000 * ru.peg_min_depth_m:.0f} mm for {ru.peg_hold_s:.2f} s)"
        out.append(f"peg       {mark(p.done)}  " + (p.note or
                   f"{1000 * p.depth_m:.1f} mm deep at most, held {p.held_s:.2f} s {need}"))
        if o.note:
            ob = o.note
        else:
            ob = (f"touched{at(o.touched_at_s)}, up to {o.max_force_n:.1f} N" if o.touched else "not touched")
            ob += ("; passed over at (" + ", ".join(f"{v:.3f}" for v in o.over_at) + f") m{at(o.done_at_s)}"
                   if o.over_at is not None else "; never passed over it")
        out.append(f"obstacle  {mark(o.done)}  {ob}")
        if g.note:
            gr = g.note
        else:
            gr = f"{100 * g.share:.0f} % of the path inside (needs {100 * ru.groove_min_share:.0f} %)"
            if g.entered_at_s is not None:
                if g.left_at is not None:
                    gr += "; left at (" + ", ".join(f"{v:.3f}" for v in g.left_at) + ") m"
                else:
                    gr += "; in it to the exit" if g.reached_exit else "; still in it when the run ended"
            gr += f"; largest side force {g.max_side_force_n:.1f} N"
        out.append(f"groove    {mark(g.done)}  {gr}")
        lo, hi = ru.band_g
        eg = e.note or (f"peak {e.peak_g:.0f} g, {e.in_band_s:.2f} s in {lo:.0f}-{hi:.0f} g "
                        f"(needs {ru.hold_s:.2f} s); "
                        + (f"BROKEN{at(e.broken_at_s)}" if e.broken else "not broken"))
        out.append(f"egg       {mark(e.done)}  {eg}")
        if self.time_s is not None:
            out.append(f"time      {self.time_s:.2f} s from the first motion "
                       f"(t = {self.first_motion_s:.2f} s) to the last task")
        else:
            out.append(f"time      none: {self.done} of 4 tasks done")
        return out


def longest_run(mask: np.ndarray) -> tuple[int, int]:
    """The longest stretch of True in ``mask``: (its length, its first index; -1 when none)."""
    m = np.asarray(mask, bool)
    if not m.any():
        return 0, -1
    edges = np.diff(np.concatenate([[0], m.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    k = int(np.argmax(ends - starts))
    return int(ends[k] - starts[k]), int(starts[k])


def first_run_reaching(mask: np.ndarray, rows: int) -> int:
    """The index at which ``mask`` has first been True ``rows`` rows in a row (-1 when never).

    >>> first_run_reaching(np.array([1, 0, 1, 1, 1], bool), 2)
    3
    """
    run = 0
    m = np.asarray(mask, bool)
    if rows <= 0:
        return 0 if len(m) else -1
    edges = np.diff(np.concatenate([[0], m.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    for s, e in zip(starts, ends):
        run = e - s
        if run >= rows:
            return int(s + rows - 1)
    return -1


def column(log: Mapping[str, np.ndarray], name: str, width: int = 1) -> np.ndarray:
    """A log column as floats: shape (n,) for width 1, (n, width) else."""
    if name not in log:
        raise ScorecardError(f"the run's scope log has no {name!r} signal (was it run in a world with "
                             "contacts?)")
    a = np.asarray(log[name], dtype=np.float64)
    if width == 1:
        return a.reshape(len(a), -1)[:, 0]
    return a.reshape(len(a), -1)[:, :width]


def score(log: Mapping[str, np.ndarray], world: Any) -> Scorecard:
    """Score one run: its scope log (one row per tick) in ``world`` (a
    :class:`crslab.world.World`). Raises :class:`ScorecardError` when a signal is missing."""
    tick = column(log, "tick")
    if len(tick) == 0:
        raise ScorecardError("the run's scope log has no rows")
    t = tick / TICKS_PER_S
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 0.001
    tip = column(log, "peg_tip", 3)
    rules = world.contest

    peg = _peg(world, rules, t, dt, tip)
    obstacle = _obstacle(world, log, t, tip)
    groove = _groove(world, rules, log, t, tip)
    egg = _egg(world, rules, log, t, dt)

    moved = np.linalg.norm(tip - tip[0], axis=1) > MOTION_M
    first = float(t[np.argmax(moved)]) if moved.any() else None
    ends = [peg.done_at_s, obstacle.done_at_s, groove.done_at_s, egg.done_at_s]
    all_done = peg.done and obstacle.done and groove.done and egg.done
    time_s = (max(ends) - first) if all_done and first is not None and None not in ends else None  # type: ignore[type-var]
    return Scorecard(peg, obstacle, groove, egg, time_s, first, rules)


def _peg(world: Any, rules: ContestRules, t: np.ndarray, dt: float, tip: np.ndarray) -> Peg:
    hole = getattr(world, "hole", None)
    if hole is None:
        return Peg(False, 0.0, 0.0, None, note=f"world {world.name!r} has no hole")
    depth = peg_depths(hole.center_xy_m, hole.top_z_m, hole.diameter_m / 2, tip)
    deep = depth >= rules.peg_min_depth_m
    rows, _ = longest_run(deep)
    need = max(1, math.ceil(rules.peg_hold_s / dt - 1e-9))
    k = first_run_reaching(deep, need)
    return Peg(k >= 0, float(depth.max()), rows * dt, float(t[k]) if k >= 0 else None)


def _obstacle(world: Any, log: Mapping[str, np.ndarray], t: np.ndarray, tip: np.ndarray) -> Obstacle:
    ob = getattr(world, "obstacle", None)
    if ob is None:
        return Obstacle(False, False, 0.0, None, False, None, None,
                        note=f"world {world.name!r} has no obstacle")
    force = column(log, "obstacle_force")
    touch = force > TOUCH_N
    (x, y), (sx, sy) = ob.center_xy_m, ob.size_xy_m
    over = ((np.abs(tip[:, 0] - x) <= sx / 2) & (np.abs(tip[:, 1] - y) <= sy / 2) & (tip[:, 2] > ob.top_z_m))
    k = int(np.argmax(over)) if over.any() else -1
    touched = bool(touch.any())
    over_at = tuple(float(v) for v in tip[k]) if k >= 0 else None
    return Obstacle(k >= 0 and not touched, touched, float(force.max()),
                    float(t[np.argmax(touch)]) if touched else None, k >= 0, over_at,  # type: ignore[arg-type]
                    float(t[k]) if k >= 0 else None)


def _groove(world: Any, rules: ContestRules, log: Mapping[str, np.ndarray], t: np.ndarray,
            tip: np.ndarray) -> Groove:
    gr = getattr(world, "groove", None)
    if gr is None:
        return Groove(False, 0.0, 0.0, None, None, None, note=f"world {world.name!r} has no groove")
    side = np.abs(column(log, "groove_side_force"))
    _, dist, arc = groove_nearest(gr.corners_xy_m, tip[:, :2])
    total = gr.length_m
    inside = ((dist <= gr.width_m / 2) & (tip[:, 2] <= gr.top_z_m)
              & (tip[:, 2] >= gr.top_z_m - gr.depth_m - DEPTH_SLACK_M))
    if not inside.any():
        return Groove(False, 0.0, float(side.max()), None, None, None)
    k0 = int(np.argmax(inside))
    outside_after = np.flatnonzero(~inside[k0:])
    k1 = k0 + int(outside_after[0]) if len(outside_after) else len(inside)   # first row out again
    stay_arc = arc[k0:k1]
    share = float(np.clip((stay_arc.max() - arc[k0]) / total, 0.0, 1.0))
    reached_end = stay_arc.max() >= total - gr.width_m / 2
    left = k1 < len(inside) and not reached_end
    left_at = (float(tip[k1, 0]), float(tip[k1, 1])) if left else None
    done = share >= rules.groove_min_share
    done_at = None
    if done:
        need_arc = arc[k0] + rules.groove_min_share * total
        done_at = float(t[k0 + int(np.argmax(stay_arc >= need_arc - 1e-12))])
    return Groove(done, share, float(side[k0:k1].max()), left_at, float(t[k0]), done_at,
                  reached_exit=bool(reached_end))


def _egg(world: Any, rules: ContestRules, log: Mapping[str, np.ndarray], t: np.ndarray, dt: float) -> Egg:
    if getattr(world, "egg", None) is None:
        return Egg(False, 0.0, 0.0, False, None, None, note=f"world {world.name!r} has no egg")
    grams = column(log, "scale_g")
    broken_rows = column(log, "egg_broken") > 0.5
    lo, hi = rules.band_g
    band = (grams >= lo) & (grams <= hi) & ~broken_rows
    rows, _ = longest_run(band)
    need = max(1, math.ceil(rules.hold_s / dt - 1e-9))
    k = first_run_reaching(band, need)
    broken = bool(broken_rows.any())
    return Egg(k >= 0 and not broken, float(grams.max()), rows * dt, broken,
               float(t[np.argmax(broken_rows)]) if broken else None, float(t[k]) if k >= 0 else None)
