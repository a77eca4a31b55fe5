"""The final project's scorecard: what one run of a lab did in the contest world, task by task, and
how the run went (where the arm rested, how the run ended, what cut it short).

:func:`score` is pure: it reads a run's scope log (one row per logged tick: the world's row of
docs/worlds.md and the board's safety flag and motor board), the world (its fixtures and its
rules, ``world.contest``) and what the run reported (:class:`RunFacts`), and returns a
:class:`Scorecard`. The tasks are judged in :mod:`crslab.contest.tasks`, the motion's start and end
in :mod:`crslab.contest.motion`; docs/contest.md says the same for students.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from crslab.contest.motion import LONGEST_S, first_motion, still_since
from crslab.contest.offsets import Rest
from crslab.contest.tasks import (
    NEAR_HOLE_M,
    Egg,
    Groove,
    Obstacle,
    Peg,
    ScorecardError,
    Trace,
    column,
    judge_egg,
    judge_groove,
    judge_obstacle,
    judge_peg,
)
from crslab.framework_facts import CLAMP_UNITS, TICKS_PER_S
from crslab.run.status import RunStatus
from crslab.traj.joint_space import crs_outside_envelope, crs_why_outside
from crslab.worker.run_stats import RunStats

__all__ = ["RunFacts", "Scorecard", "ScorecardError", "score"]

TASKS = ("peg", "obstacle", "groove", "egg")


@dataclass(frozen=True)
class RunFacts:
    """What the run itself reported: how it ended (its status and one-line message), its counters
    (lab()'s cost against the budget, the motor board's cut-outs), where the arm rested, and the
    tick lab() was first called."""

    status: RunStatus = RunStatus.OK
    message: str = ""
    end_tick: int | None = None
    """The tick the run ended at (None: after the log's last row)."""
    stats: RunStats = field(default_factory=RunStats)
    rest: Rest | None = None
    startup_ticks: int = 0
    budget: int = 0


@dataclass(frozen=True)
class Ended:
    """How the run ended, as the card says it."""

    end_s: float
    logged_s: float                 # the log's last row (the card covers the run up to there)
    status: RunStatus
    message: str
    still_since_s: float | None     # the arm came to rest for good then (s)
    moved: bool                     # the arm moved at all (the first motion)
    safety_at_s: float | None       # the framework's safety envelope first tripped (s)
    safety_why: str | None          # ... which of its limits the lab's angles crossed then
    safety_back_s: float | None     # ... when the arm was first back inside (None: never again)
    safety_clamped: tuple[int, ...]  # ... the motors (1-3) the lab held at the clamp just before it
    safety_clamped_from_s: float | None  # ... since when (within CLAMPED_BEFORE_S of the trip)
    motor_board_off_at_s: float | None
    motor_board_joint: int | None   # which joint's command cut it (0: no command came)
    over_budget: int                # lab() calls over the budget
    first_over_s: float | None

    @property
    def cut_short(self) -> bool:
        """The lab did not run to its own end: it crashed, hung, or was stopped."""
        return self.status not in (RunStatus.OK, RunStatus.UNMET)


@dataclass(frozen=True)
class Scorecard:
    """A run's four tasks, its time (None unless all four are done), and how the run went."""

    peg: Peg
    obstacle: Obstacle
    groove: Groove
    egg: Egg
    time_s: float | None
    first_motion_s: float | None
    rules: Any
    ended: Ended
    rest: Rest | None = None

    TASKS = TASKS

    @property
    def done(self) -> int:
        """How many of the four tasks are done."""
        return sum(getattr(self, t).done for t in self.TASKS)

    @property
    def complete(self) -> bool:
        """Whether all four tasks are done: the contest completed."""
        return self.done == len(self.TASKS)

    def as_dict(self) -> dict:
        """The JSON shape of docs/contest.md."""
        return card_dict(self)

    def lines(self) -> list[str]:
        """One line per task with its evidence, the time, then the run's lines."""
        return card_lines(self)


def score(log: Mapping[str, np.ndarray], world: Any, run: RunFacts | None = None) -> Scorecard:
    """Score one run: its scope log (one row per logged tick) in ``world`` (a
    :class:`crslab.world.World` with fixtures), what the run reported (``run``; None: a run
    that reached its end). Raises :class:`ScorecardError` when a signal is missing."""
    run = run if run is not None else RunFacts()
    tick = column(log, "tick")
    if len(tick) == 0:
        raise ScorecardError("the run's scope log has no rows")
    t = tick / TICKS_PER_S
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 1.0 / TICKS_PER_S
    tr = Trace(t, column(log, "peg_tip", 3), dt)
    peg, obstacle = judge_peg(log, world, tr), judge_obstacle(log, world, tr)
    groove, egg = judge_groove(log, world, tr), judge_egg(log, world, tr)
    first = first_motion(t, tr.tip)
    ends = [peg.done_at_s, obstacle.done_at_s, groove.done_at_s, egg.done_at_s]
    all_done = peg.done and obstacle.done and groove.done and egg.done
    time_s = (max(ends) - first) if all_done and first is not None and None not in ends else None  # type: ignore[type-var]
    return Scorecard(peg, obstacle, groove, egg, time_s, first, world.contest, _ended(log, t, tr, first, run),
                     run.rest)


def _ended(log: Mapping[str, np.ndarray], t: np.ndarray, tr: Trace, first: float | None,
           run: RunFacts) -> Ended:
    started = t >= run.startup_ticks / TICKS_PER_S
    safety = (column(log, "safety") > 0.5) & started if "safety" in log else np.zeros(len(t), bool)
    off = column(log, "motor_board_off") > 0.5 if "motor_board_off" in log else np.zeros(len(t), bool)
    cuts = [e for e in run.stats.motor_board_events if e[2]]
    st = run.stats
    return Ended(
        end_s=run.end_tick / TICKS_PER_S if run.end_tick is not None else float(t[-1]) + tr.dt,
        logged_s=float(t[-1]), status=run.status, message=run.message,
        still_since_s=still_since(t, tr.tip, first), moved=first is not None,
        safety_at_s=float(t[np.argmax(safety)]) if safety.any() else None,
        safety_why=_why_outside(log, safety), safety_back_s=_back_inside_s(t, safety),
        **_clamped_before(log, t, safety),
        motor_board_off_at_s=float(t[np.argmax(off)]) if off.any() else None,
        motor_board_joint=int(cuts[0][1]) if cuts else None,
        over_budget=st.over_budget,
        first_over_s=st.first_over_tick[0] / TICKS_PER_S if st.first_over_tick else None)


def _why_outside(log: Mapping[str, np.ndarray], safety: np.ndarray) -> str | None:
    """Which limit of the envelope the lab's angles (``enc_rad``) crossed on the first row the
    framework's flag is set (or the row before: the flag is the check after that tick's lab())."""
    if not safety.any() or "enc_rad" not in log:
        return None
    k = int(np.argmax(safety))
    enc = column(log, "enc_rad", 3)
    for row in (k, k - 1):
        if row >= 0 and crs_outside_envelope(enc[row])[0]:
            return crs_why_outside(enc[row])
    return None


CLAMPED_BEFORE_S = 0.1
"""How long before the envelope tripped the card looks for the lab's commands at the clamp (s)."""


def _clamped_before(log: Mapping[str, np.ndarray], t: np.ndarray, safety: np.ndarray) -> dict:
    """The motors whose command from the lab (``tau_lab``, before the framework clamps it) was at
    the clamp or beyond in the :data:`CLAMPED_BEFORE_S` up to the envelope's first trip, and since
    when: a controller driving the arm as hard as the board lets it out of the envelope (a gain too
    high, a speed estimate that starts from zero and sees the offsets as a jump).

    >>> t = np.arange(6) / 1000
    >>> tau = np.array([[0, 1, 1], [0, 6, 5], [0, -40, 5], [0, 5, 1], [0, 0, 0], [0, 0, 0]], float)
    >>> _clamped_before({"tau_lab": tau}, t, np.array([0, 0, 0, 0, 1, 1], bool))
    {'safety_clamped': (2, 3), 'safety_clamped_from_s': 0.001}
    """
    if not safety.any() or "tau_lab" not in log:
        return {"safety_clamped": (), "safety_clamped_from_s": None}
    k = int(np.argmax(safety))
    window = (t >= t[k] - CLAMPED_BEFORE_S) & (np.arange(len(t)) <= k)
    at_clamp = (np.abs(column(log, "tau_lab", 3)) >= CLAMP_UNITS) & window[:, None]
    motors = tuple(int(j) + 1 for j in np.flatnonzero(at_clamp.any(axis=0)))
    rows = np.flatnonzero(at_clamp.any(axis=1))
    return {"safety_clamped": motors, "safety_clamped_from_s": float(t[rows[0]]) if len(rows) else None}


def _back_inside_s(t: np.ndarray, safety: np.ndarray) -> float | None:
    """The first time after the envelope first tripped that the framework's flag is clear again."""
    if not safety.any():
        return None
    k = int(np.argmax(safety))
    clear = np.flatnonzero(~safety[k:])
    return float(t[k + clear[0]]) if len(clear) else None


# -- the card's text and JSON ------------------------------------------------------------------

def _at(t: float | None) -> str:
    return "" if t is None else f" at t = {t:.2f} s"


def _point(p: tuple[float, ...]) -> str:
    return "(" + ", ".join(f"{v:.3f}" for v in p) + ") m"


def _mark(done: bool) -> str:
    return "done" if done else "FAIL"


def _peg_line(p: Peg, ru: Any) -> str:
    if p.note:
        return p.note
    need = (f"(needs {1000 * ru.peg_min_depth_m:.0f} mm for {ru.peg_hold_s:.2f} s; a TA allows "
            f"{ru.peg_hold_s - ru.hold_tolerance_s:.2f} s)")
    text = f"{1000 * p.depth_m:.1f} mm deep at most, held {p.held_s:.2f} s {need}"
    if not p.done and p.stopped_at is not None and not p.came_near:
        text += (f"; it never came within {1000 * NEAR_HOLE_M:.0f} mm of the hole's axis (nearest "
                 f"{1000 * p.off_axis_m:.0f} mm, at {_point(p.stopped_at)})")
    elif not p.done and p.stopped_at is not None:
        where = f"{1000 * p.above_top_m:.0f} mm above the hole's top" if p.above_top_m >= 0 else \
            f"{-1000 * p.above_top_m:.0f} mm below the hole's top"
        text += (f"; it stopped {1000 * p.off_axis_m:.0f} mm from the hole's axis, {where}, at "
                 f"{_point(p.stopped_at)}")
    return text


def _obstacle_line(o: Obstacle) -> str:
    if o.note:
        return o.note
    if o.touches:
        text = "touched by " + ", ".join(f"the {x.part}{_at(x.first_s)} (up to {x.max_force_n:.1f} N)"
                                          for x in o.touches)
    else:
        text = "not touched"
    if o.passed == "over":
        text += f"; passed over it at {_point(o.passed_at)}"  # type: ignore[arg-type]
    elif o.passed == "around":
        text += f"; passed around it, {1000 * o.beside_m:.0f} mm from its side, at {_point(o.passed_at)}"  # type: ignore[arg-type,operator]
    else:
        text += "; never passed it on the way from the hole to the groove"
    return text + _at(o.done_at_s)


def _groove_line(g: Groove, ru: Any) -> str:
    if g.note:
        return g.note
    text = f"{100 * g.share:.0f} % of the path inside (needs {100 * ru.groove_min_share:.0f} %)"
    if g.entered_at_s is None:
        if g.lowest_above_top_m is not None:
            text += (f"; never below the plate's top over it: the tip's lowest over the channel "
                     f"{1000 * g.lowest_above_top_m:.1f} mm above the top")
        elif g.nearest_m is not None:
            text += f"; never over the channel: {1000 * g.nearest_m:.0f} mm from its centre line at the " \
                "nearest"
    else:
        if g.left_at is not None:
            text += "; left at " + _point(g.left_at)
        elif g.reached_exit:
            text += "; in it to the exit"
        else:
            text += "; still in it when the run ended"
        if g.stuck_at is not None:
            text += f"; it stayed at {_point(g.stuck_at)} from t = {g.stuck_from_s:.2f} s"
    return text + f"; largest side force {g.max_side_force_n:.1f} N"


def _egg_line(e: Egg, ru: Any) -> str:
    if e.note:
        return e.note
    lo, hi = ru.band_g
    need = ru.hold_s - ru.hold_tolerance_s
    text = (f"peak {e.peak_g:.0f} g, {e.in_band_s:.2f} s in {lo:.0f}-{hi:.0f} g (needs {ru.hold_s:.2f} s; "
            f"a TA allows {need:.2f} s)")
    if e.broken:
        text += (f"; BROKEN{_at(e.broken_at_s)} by {e.broken_by}, the press's peak before it "
                 f"{e.peak_before_break_g:.0f} g")
    elif not e.touched:
        if e.lowest_above_top_m is not None:
            text += (f"; never touched: the tip's lowest over it {1000 * e.lowest_above_top_m:.1f} mm above "
                     "its top")
            if e.breakaway_n is not None:
                text += (f"; the arm rested there from t = {e.rested_from_s:.2f} s for "
                         f"{e.rested_for_s:.1f} s: from rest at that pose its joints' static friction holds "
                         f"it against a push down at the tip under about {e.breakaway_n:.0f} N")
        else:
            text += "; never touched: the tip never came over it"
    else:
        text += "; not broken"
    if e.touched_at_s is not None:
        speed = (f" coming down at {1000 * e.touch_speed_m_s:.0f} mm/s" if e.touch_speed_m_s is not None
                 else "")
        text += f"; first touched at t = {e.touched_at_s:.2f} s{speed}"
    return text


def card_lines(card: Scorecard) -> list[str]:
    """The card's text: see :meth:`Scorecard.lines`."""
    ru = card.rules
    out = [
        f"peg       {_mark(card.peg.done)}  {_peg_line(card.peg, ru)}",
        f"obstacle  {_mark(card.obstacle.done)}  {_obstacle_line(card.obstacle)}",
        f"groove    {_mark(card.groove.done)}  {_groove_line(card.groove, ru)}",
        f"egg       {_mark(card.egg.done)}  {_egg_line(card.egg, ru)}",
    ]
    if card.time_s is not None:
        out.append(f"time      {card.time_s:.2f} s from the first motion (t = {card.first_motion_s:.2f} s) "
                   "to the last task")
    else:
        out.append(f"time      none: {card.done} of 4 tasks done")
    if card.rest is not None:
        out.append(card.rest.line())
    out.extend(_run_lines(card.ended))
    return out


def _run_lines(e: Ended) -> list[str]:
    out = []
    if e.cut_short:
        out.append(f"run       {e.status} at t = {e.end_s:.3f} s: {e.message}; the card covers the run up to "
                   f"t = {e.logged_s:.3f} s")
    elif not e.moved:
        out.append(f"run       ended at t = {e.end_s:.2f} s: the arm never moved")
    elif e.still_since_s is not None:
        out.append(f"run       ended at t = {e.end_s:.2f} s: the arm at rest since t = "
                   f"{e.still_since_s:.2f} s")
    elif e.end_s >= LONGEST_S - 1e-9:
        out.append(f"run       ended at t = {e.end_s:.2f} s, the longest contest run: the arm still moving")
    else:
        out.append(f"run       ended at t = {e.end_s:.2f} s")
    if e.safety_at_s is not None:
        why = f" ({e.safety_why})" if e.safety_why else ""
        back = (f"; the arm back inside at t = {e.safety_back_s:.2f} s" if e.safety_back_s is not None
                else " and kept the arm to the end of the run: the lab's torques were not used again")
        clamped = ""
        if e.safety_clamped:
            names = " and ".join(", ".join(map(str, e.safety_clamped)).rsplit(", ", 1))
            plural = "s" if len(e.safety_clamped) > 1 else ""
            clamped = (f"; before it the lab commanded motor{plural} {names} at the clamp ({CLAMP_UNITS:g} "
                       f"units) from t = {e.safety_clamped_from_s:.3f} s")
        out.append(f"safety    the arm left the safety envelope at t = {e.safety_at_s:.2f} s{why}{clamped}: "
                   f"the framework's hold took over from the lab{back}")
    if e.motor_board_off_at_s is not None:
        why = {None: "", 0: " (no command came)"}.get(
            e.motor_board_joint, f" (joint {e.motor_board_joint} commanded over its limit)")
        out.append(f"motors    the motor board cut every output at t = {e.motor_board_off_at_s:.2f} s{why}")
    if e.over_budget:
        out.append(f"budget    {e.over_budget} lab() calls over the budget (the first at t = "
                   f"{e.first_over_s:.3f} s): on the board they would miss their ticks")
    return out


def card_dict(card: Scorecard) -> dict:
    """The card as one JSON object (docs/contest.md)."""
    def r(v: float | None, nd: int = 4) -> float | None:
        return None if v is None else round(float(v), nd)

    def pt(p: tuple[float, ...] | None) -> list | None:
        return None if p is None else [r(v) for v in p]

    p, o, g, e, end = card.peg, card.obstacle, card.groove, card.egg, card.ended
    return {
        "complete": card.complete,
        "tasks": {
            "peg": {"done": p.done, "done_at_s": r(p.done_at_s, 3), "depth_m": r(p.depth_m),
                    "held_s": r(p.held_s, 3), "stopped_at": pt(p.stopped_at), "off_axis_m": r(p.off_axis_m)},
            "obstacle": {"done": o.done, "done_at_s": r(o.done_at_s, 3), "touched": o.touched,
                         "touched_by": [x.part for x in o.touches], "max_force_n": r(o.max_force_n, 3),
                         "passed": o.passed, "passed_at": pt(o.passed_at)},
            "groove": {"done": g.done, "done_at_s": r(g.done_at_s, 3), "share": r(g.share, 3),
                       "max_side_force_n": r(g.max_side_force_n, 3), "left_at": pt(g.left_at),
                       "stuck_at": pt(g.stuck_at), "lowest_above_top_m": r(g.lowest_above_top_m)},
            "egg": {"done": e.done, "done_at_s": r(e.done_at_s, 3), "peak_g": r(e.peak_g, 1),
                    "in_band_s": r(e.in_band_s, 3), "broken": e.broken, "broken_by": e.broken_by,
                    "peak_before_break_g": r(e.peak_before_break_g, 1),
                    "lowest_above_top_m": r(e.lowest_above_top_m), "rested_from_s": r(e.rested_from_s, 3),
                    "breakaway_n": r(e.breakaway_n, 1), "touched_at_s": r(e.touched_at_s, 3),
                    "touch_speed_m_s": r(e.touch_speed_m_s, 4)},
        },
        "time_s": r(card.time_s, 3),
        "rest": None if card.rest is None else {"motor_rad": [r(v, 6) for v in card.rest.motor_rad],
                                                "source": card.rest.source},
        "run": {"status": str(end.status), "end_s": r(end.end_s, 3), "message": end.message,
                "still_since_s": r(end.still_since_s, 3), "safety_at_s": r(end.safety_at_s, 3),
                "safety_why": end.safety_why, "safety_back_s": r(end.safety_back_s, 3),
                "safety_clamped": list(end.safety_clamped),
                "safety_clamped_from_s": r(end.safety_clamped_from_s, 3),
                "motor_board_off_at_s": r(end.motor_board_off_at_s, 3), "over_budget": end.over_budget},
    }
