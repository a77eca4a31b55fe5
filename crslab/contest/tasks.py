"""The contest's four tasks judged from a run's scope log, each with the evidence a TA would give.

Every function here is pure: it reads the log's columns (one row per logged tick; the world's
row of docs/worlds.md: ``peg_tip``, ``peg_depth``, the forces on each fixture and on the obstacle
by each part of the arm, the scale's grams, how the egg broke, where along the groove the tip is)
and the world's fixtures and rules (``world.contest``), and returns the task's evidence. Nothing
is worked out again that the C world computes once (the peg's depth, the groove's nearest
segment, how the egg broke): the log's columns are read as they are.

>>> import numpy as np
>>> longest_run(np.array([1, 1, 0, 1, 1, 1, 0], bool))
(3, 3)
>>> first_run_reaching(np.array([1, 0, 1, 1, 1], bool), 2)
3
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from crslab.world.world_facts import EGG_BROKEN_BY, TOUCH_N

DEPTH_SLACK_M = 0.005
"""Below the groove's floor by this much (m) still counts as in it (the contact's penetration)."""
NEAR_HOLE_M = 0.03
"""Where the peg stopped when it missed the hole: its lowest point this near (m, across) the hole's axis."""
STUCK_S = 1.0
"""A peg in the groove that moves less than :data:`STUCK_M` for this long (s) is stuck there."""
STUCK_M = 0.002
AT_REST_M = 0.0005
"""A tip that stays within this (m) of a point for :data:`AT_REST_S` (s) came to rest there."""
AT_REST_S = 0.5
OBSTACLE_PARTS = (("peg", "obstacle_peg_force"), ("forearm", "obstacle_forearm_force"),
                  ("upper arm", "obstacle_upper_arm_force"))
"""The parts of the arm the world tells apart on the obstacle, and their log columns."""


class ScorecardError(ValueError):
    """The scope log cannot be scored (a signal missing, no rows); its str is one line."""


def column(log: Mapping[str, np.ndarray], name: str, width: int = 1) -> np.ndarray:
    """A log column as floats: shape (n,) for width 1, (n, width) else."""
    if name not in log:
        raise ScorecardError(f"the run's scope log has no {name!r} signal (was it run in a world with "
                             "contacts?)")
    a = np.asarray(log[name], dtype=np.float64)
    if width == 1:
        return a.reshape(len(a), -1)[:, 0]
    return a.reshape(len(a), -1)[:, :width]


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
    """The index at which ``mask`` has first been True ``rows`` rows in a row (-1 when never)."""
    m = np.asarray(mask, bool)
    if rows <= 0:
        return 0 if len(m) else -1
    edges = np.diff(np.concatenate([[0], m.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    for s, e in zip(starts, ends):
        if e - s >= rows:
            return int(s + rows - 1)
    return -1


def _across(tr: Trace, center_xy: tuple[float, float]) -> np.ndarray:
    """Each row's tip's distance (m, across: in x-y) from a vertical axis through ``center_xy``."""
    return np.hypot(tr.tip[:, 0] - center_xy[0], tr.tip[:, 1] - center_xy[1])


def _xyz(p: np.ndarray) -> tuple[float, float, float]:
    return (float(p[0]), float(p[1]), float(p[2]))


@dataclass(frozen=True)
class Trace:
    """What every task reads: the rows' times (s), the peg's tip (m), the row time step (s)."""

    t: np.ndarray
    tip: np.ndarray
    dt: float

    def rows(self, seconds: float) -> int:
        """How many rows last ``seconds`` (at least 1)."""
        return max(1, math.ceil(seconds / self.dt - 1e-9))


# -- the peg ------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Peg:
    done: bool
    depth_m: float          # deepest the tip went below the hole's top, in the hole
    held_s: float           # longest stay at least the rules' depth deep
    done_at_s: float | None
    stopped_at: tuple[float, float, float] | None = None
    """When not done: the tip's lowest point near the hole (m), where it stopped; when it never came
    :data:`NEAR_HOLE_M` near the hole's axis, its nearest point (``came_near`` False)."""
    came_near: bool = True
    off_axis_m: float | None = None    # ... its distance across from the hole's axis
    above_top_m: float | None = None   # ... its height above the hole's top (negative: below)
    note: str = ""          # why it cannot be scored (no hole in the world)


def judge_peg(log: Mapping[str, np.ndarray], world: Any, tr: Trace) -> Peg:
    hole, rules = world.hole, world.contest
    if hole is None:
        return Peg(False, 0.0, 0.0, None, note=f"world {world.name!r} has no hole")
    depth = column(log, "peg_depth")
    deep = depth >= rules.peg_min_depth_m
    rows, _ = longest_run(deep)
    k = first_run_reaching(deep, tr.rows(rules.peg_hold_s - rules.hold_tolerance_s))
    if k >= 0:
        return Peg(True, float(depth.max()), rows * tr.dt, float(tr.t[k]))
    off = _across(tr, hole.center_xy_m)
    near = np.flatnonzero(off <= NEAR_HOLE_M)
    # the lowest point near the axis; never near: the nearest (the lowest of those)
    at = int(near[np.argmin(tr.tip[near, 2])]) if len(near) else int(np.lexsort((tr.tip[:, 2], off))[0])
    return Peg(False, float(depth.max()), rows * tr.dt, None, stopped_at=_xyz(tr.tip[at]),
               came_near=bool(len(near)), off_axis_m=float(off[at]),
               above_top_m=float(tr.tip[at, 2] - hole.top_z_m))


# -- the obstacle -------------------------------------------------------------------------------

@dataclass(frozen=True)
class Touch:
    part: str               # peg, forearm, upper arm
    first_s: float
    max_force_n: float


@dataclass(frozen=True)
class Obstacle:
    done: bool
    touches: tuple[Touch, ...]     # each part of the arm that touched it, first touch first
    max_force_n: float
    passed: str | None             # "over", "around", or None: never passed it
    passed_at: tuple[float, float, float] | None   # where the tip crossed its line (m)
    beside_m: float | None         # passing around: how far from its side (m)
    done_at_s: float | None
    note: str = ""

    @property
    def touched(self) -> bool:
        return bool(self.touches)


def _box_distance_xy(p: np.ndarray, center: tuple, size: tuple) -> float:
    d = np.maximum(np.abs(p[:2] - np.asarray(center)) - np.asarray(size) / 2, 0.0)
    return float(np.hypot(*d))


def judge_obstacle(log: Mapping[str, np.ndarray], world: Any, tr: Trace) -> Obstacle:
    """Touched when a part of the arm ever pressed it harder than :data:`TOUCH_N`; passed when the
    tip crossed the obstacle's line (through its centre, across the way from the hole to the
    groove's entrance) from the hole's side: over it (above its top inside its footprint) or, when
    the rules allow it, around it; done when passed and never touched."""
    ob, rules = world.obstacle, world.contest
    if ob is None:
        return Obstacle(False, (), 0.0, None, None, None, None, note=f"world {world.name!r} has no obstacle")
    touches = []
    for part, name in OBSTACLE_PARTS:
        f = column(log, name)
        hit = np.flatnonzero(f > TOUCH_N)
        if len(hit):
            touches.append(Touch(part, float(tr.t[hit[0]]), float(f.max())))
    touches.sort(key=lambda x: x.first_s)
    total = column(log, "obstacle_force")
    center, size, top = np.asarray(ob.center_xy_m), np.asarray(ob.size_xy_m), ob.top_z_m
    over = ((np.abs(tr.tip[:, 0] - center[0]) <= size[0] / 2)
            & (np.abs(tr.tip[:, 1] - center[1]) <= size[1] / 2) & (tr.tip[:, 2] > top))
    passed = at = beside = done_at = None
    if world.hole is not None and world.groove is not None:
        way = np.asarray(world.groove.corners_xy_m[0]) - np.asarray(world.hole.center_xy_m)
        way = way / np.hypot(*way)
        s = (tr.tip[:, :2] - center) @ way
        cross = np.flatnonzero((s[:-1] < 0) & (s[1:] >= 0)) + 1
        for k in cross:
            k = int(k)
            if over[k] or over[max(0, k - 1)]:
                passed, at, done_at = "over", _xyz(tr.tip[k]), float(tr.t[k])
                break
            if rules.obstacle_around and passed is None:
                passed, at, done_at = "around", _xyz(tr.tip[k]), float(tr.t[k])
                beside = _box_distance_xy(tr.tip[k], ob.center_xy_m, ob.size_xy_m)
                break
    elif over.any():  # no way from a hole to a groove to cross: over its top is passing it
        k = int(np.argmax(over))
        passed, at, done_at = "over", _xyz(tr.tip[k]), float(tr.t[k])
    done = passed is not None and not touches
    return Obstacle(done, tuple(touches), float(total.max()), passed, at, beside, done_at if done else None)


# -- the groove ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class Groove:
    done: bool
    share: float            # of the Z's centre line covered in the stay inside that covers most (0..1)
    max_side_force_n: float
    entered_at_s: float | None
    done_at_s: float | None
    left_at: tuple[float, float] | None = None     # where the tip left before the exit (m)
    reached_exit: bool = False
    stuck_at: tuple[float, float] | None = None    # where it stayed without moving on (m)
    stuck_from_s: float | None = None
    lowest_above_top_m: float | None = None   # never in it: the tip's lowest over the channel, above the top
    nearest_m: float | None = None         # never over the channel: how near its centre line it came
    note: str = ""


def judge_groove(log: Mapping[str, np.ndarray], world: Any, tr: Trace) -> Groove:
    """Inside while the tip is within half the groove's width of the Z's centre line and below the
    plate's top (down to its floor, with :data:`DEPTH_SLACK_M`). Of the stays inside, the one that
    covers the most of the Z's length (a tip that slides along the plate's top at the mouth and
    brushes the channel's edge for a moment before it drops in has not followed the groove for that
    moment, nor left it); done when its share reaches the rules'."""
    gr, rules = world.groove, world.contest
    if gr is None:
        return Groove(False, 0.0, 0.0, None, None, note=f"world {world.name!r} has no groove")
    side = np.abs(column(log, "groove_side_force"))
    offset, along = column(log, "groove_offset"), column(log, "groove_along")
    corners = np.asarray(gr.corners_xy_m, dtype=np.float64)
    total = float(np.sum(np.hypot(*np.diff(corners, axis=0).T)))
    over = offset <= gr.width_m / 2
    z = tr.tip[:, 2]
    inside = over & (z <= gr.top_z_m) & (z >= gr.top_z_m - gr.depth_m - DEPTH_SLACK_M)
    if not inside.any():
        if over.any():
            k = int(np.flatnonzero(over)[np.argmin(z[over])])
            return Groove(False, 0.0, float(side.max()), None, None,
                          lowest_above_top_m=float(z[k] - gr.top_z_m))
        return Groove(False, 0.0, float(side.max()), None, None, nearest_m=float(offset.min()))
    k0, k1 = _longest_stay(inside, along)
    stay = along[k0:k1]
    share = float(np.clip((stay.max() - along[k0]) / total, 0.0, 1.0))
    reached_exit = bool(stay.max() >= total - gr.width_m / 2)
    left = k1 < len(inside) and not reached_exit
    done = share >= rules.groove_min_share
    done_at = None
    if done:
        need = along[k0] + rules.groove_min_share * total
        done_at = float(tr.t[k0 + int(np.argmax(stay >= need - 1e-12))])
    stuck_at = stuck_from = None
    if not done:
        stuck_at, stuck_from = _stuck(tr, k0, k1)
    return Groove(done, share, float(side[k0:k1].max()), float(tr.t[k0]), done_at,
                  left_at=(float(tr.tip[k1, 0]), float(tr.tip[k1, 1])) if left else None,
                  reached_exit=reached_exit, stuck_at=stuck_at, stuck_from_s=stuck_from)


def _longest_stay(inside: np.ndarray, along: np.ndarray) -> tuple[int, int]:
    """The rows ``[k0, k1)`` of the stay inside (a run of ``inside`` rows) over which the tip went
    furthest along the Z from where it entered; the first such stay when several go as far.

    >>> inside = np.array([0, 1, 0, 0, 1, 1, 1, 0], bool)
    >>> _longest_stay(inside, np.array([0, 0.01, 0, 0, 0.01, 0.05, 0.09, 0.1]))
    (4, 7)
    """
    edges = np.flatnonzero(np.diff(np.concatenate(([0], inside.astype(np.int8), [0]))))
    starts, ends = edges[::2], edges[1::2]
    covered = [along[a:b].max() - along[a] for a, b in zip(starts, ends, strict=True)]
    best = int(np.argmax(covered))
    return int(starts[best]), int(ends[best])


def _stuck(tr: Trace, k0: int, k1: int) -> tuple[tuple[float, float] | None, float | None]:
    """Where the tip stood still inside the groove (within :data:`STUCK_M` for :data:`STUCK_S`)
    before it left or the run ended, and since when; (None, None) when it never did."""
    need = tr.rows(STUCK_S)
    xy = tr.tip[k0:k1, :2]
    for k in range(need, len(xy) + 1, max(1, need // 4)):
        window = xy[k - need:k]
        if np.max(np.hypot(*(window - window[-1]).T)) <= STUCK_M:
            start = k - need
            return (float(window[-1, 0]), float(window[-1, 1])), float(tr.t[k0 + start])
    return None, None


# -- the egg ------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Egg:
    done: bool
    peak_g: float
    in_band_s: float        # longest unbroken time within the band
    broken: bool
    broken_at_s: float | None
    done_at_s: float | None
    broken_by: str | None = None        # the press, a side hit, a fall
    peak_before_break_g: float | None = None
    touched: bool = True
    lowest_above_top_m: float | None = None   # never touched: the tip's lowest over the egg, above its top
    rested_from_s: float | None = None        # ... when the arm came to rest there (for at least AT_REST_S)
    rested_for_s: float | None = None
    breakaway_n: float | None = None
    """... the push down at the tip (N) that moves the arm from rest at that pose with x and y held:
    :func:`breakaway_down_n`."""
    touched_at_s: float | None = None         # touched: when the peg first pressed it
    touch_speed_m_s: float | None = None
    """... how fast the tip came down onto it then (m/s): a touch alone presses the egg about
    ``v sqrt(k m)`` and the joints' static friction can hold that (docs/worlds.md)."""
    note: str = ""


def breakaway_down_n(dh_rad: np.ndarray) -> float:
    """The push straight down at the tip (N) under which the arm, at rest at the DH angles
    ``dh_rad`` (rad) with x and y held, stays put: each motor's static band edge (crslab's plant,
    N.m) times how far that motor turns (rad) per metre the tip goes down, summed (virtual work;
    docs/worlds.md, "What presses do on it"). The push is what the lab's torques and the arm's
    weight leave together.

    At the egg of docs/worlds.md (motor angles 0.68, 0.47, 0.80 rad), 3.0 rad of motor 2 and 3.7 of
    motor 3 per metre down, both positive: 3.0 Spos2 + 3.7 Spos3.

    >>> from crslab import crs
    >>> round(breakaway_down_n(crs.motor_to_dh([0.68, 0.47, 0.80])), 1)
    16.9
    """
    from crslab import crs
    from crslab.plant.plant_params import PlantParams

    motor = crs.dh_to_motor(dh_rad)
    down_in = np.linalg.solve(crs.jacobian(motor), [0.0, 0.0, -1.0])  # rad per inch down
    per_m = down_in / 0.0254
    plant = PlantParams.defaults()
    edges = [plant.static_band_nm(m)[1] if turn > 0 else -plant.static_band_nm(m)[0]
             for m, turn in zip((1, 2, 3), per_m)]
    return float(sum(edge * abs(turn) for edge, turn in zip(edges, per_m)))


def judge_egg(log: Mapping[str, np.ndarray], world: Any, tr: Trace) -> Egg:
    """The scale's grams; the longest unbroken time within the band while the egg is whole; done
    when that reaches the rules' hold (``hold_s`` less the TA's ``hold_tolerance_s``) and the egg
    never broke."""
    egg, rules = world.egg, world.contest
    if egg is None:
        return Egg(False, 0.0, 0.0, False, None, None, note=f"world {world.name!r} has no egg")
    grams = column(log, "scale_g")
    force = column(log, "egg_force")
    broken_rows = column(log, "egg_broken") > 0.5
    lo, hi = rules.band_g
    band = (grams >= lo) & (grams <= hi) & ~broken_rows
    rows, _ = longest_run(band)
    k = first_run_reaching(band, tr.rows(rules.hold_s - rules.hold_tolerance_s))
    broken = bool(broken_rows.any())
    at = int(np.argmax(broken_rows)) if broken else -1
    by = None
    if broken:
        code = int(round(column(log, "egg_broken_by")[at]))
        by = EGG_BROKEN_BY.get(code, f"code {code}")
    touched = bool((force > TOUCH_N).any())
    lowest = rested_from = rested_for = breakaway = touched_at = touch_speed = None
    if touched:
        first = int(np.argmax(force > TOUCH_N))
        touched_at = float(tr.t[first])
        if "egg_touch_speed" in log:  # the world row's: the tip's speed down as this contact began
            touch_speed = float(column(log, "egg_touch_speed")[first])
    if not touched:
        over = _across(tr, egg.center_xy_m) <= egg.diameter_m / 2
        if over.any():
            low = int(np.flatnonzero(over)[np.argmin(tr.tip[over, 2])])
            lowest = float(tr.tip[low, 2] - egg.top_z_m)
            # the stretch of rows around the lowest one within AT_REST_M of it
            away = np.flatnonzero(np.linalg.norm(tr.tip - tr.tip[low], axis=1) > AT_REST_M)
            start = int(away[away < low].max()) + 1 if (away < low).any() else 0
            end = int(away[away > low].min()) if (away > low).any() else len(tr.tip)
            if (end - start) * tr.dt >= AT_REST_S - 1e-9 and "qpos_dh_rad" in log:  # the arm's true DH angles
                rested_from, rested_for = float(tr.t[start]), (end - start) * tr.dt
                breakaway = breakaway_down_n(column(log, "qpos_dh_rad", 3)[low])
    return Egg(k >= 0 and not broken, float(grams.max()), rows * tr.dt, broken,
               float(tr.t[at]) if broken else None, float(tr.t[k]) if k >= 0 and not broken else None,
               broken_by=by,
               peak_before_break_g=float(grams[:at].max()) if at > 0 else (0.0 if broken else None),
               touched=touched, lowest_above_top_m=lowest, rested_from_s=rested_from, rested_for_s=rested_for,
               breakaway_n=breakaway, touched_at_s=touched_at, touch_speed_m_s=touch_speed)
