"""The contest's scorecard on hand-made scope logs: each expected score is worked out by hand from
the trace's keyframes (1 ms rows) and the small layout below, not by the scorecard's code."""

from types import SimpleNamespace

import numpy as np
import pytest

from crslab.contest.scorecard import DEPTH_SLACK_M, MOTION_M, ScorecardError, score
from crslab.world.fixtures import ContestRules
from crslab.world.world_facts import TOUCH_N

MS = 0.001


def layout(**missing):
    """A small contest layout: the hole at (0, 0.3) with its top at z 0.15 (2 cm wide); an obstacle
    4 x 4 x 10 cm centred at (0.2, 0.1, 0.25) (top z 0.30); a Z groove of three 10 cm segments
    (0.4, 0.1) -> (0.4, 0) -> (0.3, 0) -> (0.3, -0.1), top z 0.20, 2 cm wide, 1 cm deep; an egg."""
    world = SimpleNamespace(
        name="hand",
        hole=SimpleNamespace(center_xy_m=(0.0, 0.3), top_z_m=0.15, diameter_m=0.02, depth_m=0.04),
        obstacle=SimpleNamespace(center_xy_m=(0.2, 0.1), top_z_m=0.30, size_xy_m=(0.04, 0.04)),
        groove=SimpleNamespace(corners_xy_m=((0.4, 0.1), (0.4, 0.0), (0.3, 0.0), (0.3, -0.1)), top_z_m=0.2,
                               width_m=0.02, depth_m=0.01, length_m=0.3),
        egg=SimpleNamespace(center_xy_m=(0.2, 0.2), top_z_m=0.3),
        contest=ContestRules(band_g=(500.0, 1000.0), hold_s=2.0, peg_min_depth_m=0.01, peg_hold_s=0.5,
                             groove_min_share=0.9),
    )
    for k in missing:
        setattr(world, k, None)
    return world


def trace(keys, end_s=None, **signals):
    """A scope log at 1 ms from keyframes ``[(t_s, x, y, z), ...]`` (linear between them, held after
    the last) and ``signals``: name -> function of t (s) or constant; missing world signals are 0."""
    keys = np.asarray(keys, float)
    end = end_s if end_s is not None else keys[-1, 0]
    tick = np.arange(0, int(round(end * 1000)) + 1)
    t = tick * MS
    tip = np.stack([np.interp(t, keys[:, 0], keys[:, k]) for k in (1, 2, 3)], axis=1)
    log = {"tick": tick[:, None].astype(np.int64), "peg_tip": tip}
    for name in ("egg_force", "scale_g", "egg_broken", "hole_force", "obstacle_force", "groove_side_force",
                 "groove_force", "table_force"):
        f = signals.get(name, 0.0)
        values = np.asarray([f(v) for v in t], float) if callable(f) else np.full(len(t), float(f))
        log[name] = values[:, None]
    return log


# -- the peg ------------------------------------------------------------------------------------

def test_peg_in_the_hole_deep_enough_long_enough():
    # down the hole's axis from z 0.20 (t 1 s) to 0.13 (t 2 s: 2 cm below the top), held to 3 s,
    # up again to 0.20 at 4 s. At least 1 cm deep means z <= 0.14: from t = 1 + 0.06/0.07 s to
    # 3 + 0.01/0.07 s, 1.2857 s; done 0.5 s after it got there.
    log = trace([(0, 0, 0.3, 0.2), (1, 0, 0.3, 0.2), (2, 0, 0.3, 0.13), (3, 0, 0.3, 0.13), (4, 0, 0.3, 0.2)])
    card = score(log, layout())
    assert card.peg.done
    assert card.peg.depth_m == pytest.approx(0.02, abs=1e-9)
    assert card.peg.held_s == pytest.approx((3 + 1 / 7) - (1 + 6 / 7), abs=0.002)
    assert card.peg.done_at_s == pytest.approx(1 + 6 / 7 + 0.5, abs=0.002)


def test_peg_beside_the_hole_has_no_depth_and_a_short_stay_is_not_enough():
    off = trace([(0, 0.015, 0.3, 0.2), (1, 0.015, 0.3, 0.10), (3, 0.015, 0.3, 0.10)])  # 1.5 cm off: outside
    card = score(off, layout())
    assert (card.peg.done, card.peg.depth_m, card.peg.held_s) == (False, 0.0, 0.0)
    # in the hole, 1.5 cm deep from t 1.0 to 1.3 s; at least 1 cm (z <= 0.14) from 0.06/0.065 s on the
    # way down to 1.3 + 0.7 * 0.005/0.065 s on the way up: 0.43 s, short of 0.5 s
    short = trace([(0, 0, 0.3, 0.2), (1, 0, 0.3, 0.135), (1.3, 0, 0.3, 0.135), (2, 0, 0.3, 0.2)])
    card = score(short, layout())
    held = 1.3 + 0.7 * 0.005 / 0.065 - 0.06 / 0.065
    assert not card.peg.done and card.peg.held_s == pytest.approx(held, abs=0.002)
    assert card.peg.depth_m == pytest.approx(0.015)
    assert card.lines()[0] == (f"peg       FAIL  15.0 mm deep at most, held {held:.2f} s "
                               "(needs 10 mm for 0.50 s)")


# -- the obstacle -------------------------------------------------------------------------------

def test_obstacle_passed_over_untouched_and_touched():
    # from (0.2, 0.3, 0.35) straight along -y over the footprint (y 0.08..0.12) at z 0.35 > top 0.30
    keys = [(0, 0.2, 0.3, 0.35), (2, 0.2, -0.1, 0.35)]
    card = score(trace(keys), layout())
    o = card.obstacle
    assert o.done and o.passed_over and not o.touched
    # first row over it: y <= 0.12, at t = (0.3 - 0.12) / 0.2 s
    assert o.done_at_s == pytest.approx(0.9, abs=0.002) and o.over_at[1] == pytest.approx(0.12, abs=0.0003)
    touched = trace(keys, obstacle_force=lambda t: 3.0 if 1.0 <= t < 1.1 else 0.0)
    o = score(touched, layout()).obstacle
    assert o.touched and not o.done and o.max_force_n == 3.0 and o.touched_at_s == pytest.approx(1.0)
    # a force at the threshold is no touch; just above it is
    assert not score(trace(keys, obstacle_force=TOUCH_N), layout()).obstacle.touched
    assert score(trace(keys, obstacle_force=TOUCH_N * 1.01), layout()).obstacle.touched


def test_obstacle_not_passed_over_is_not_done_even_untouched():
    low = trace([(0, 0.2, 0.3, 0.29), (2, 0.2, -0.1, 0.29)])   # below the top (an arm through it)
    o = score(low, layout()).obstacle
    assert not o.passed_over and not o.done and o.over_at is None


# -- the groove ---------------------------------------------------------------------------------

GROOVE_Z = 0.195   # 5 mm below the plate's top, in the groove


def test_groove_followed_corner_to_corner():
    keys = [(0, 0.4, 0.1, 0.25), (1, 0.4, 0.1, GROOVE_Z), (2, 0.4, 0.0, GROOVE_Z), (3, 0.3, 0.0, GROOVE_Z),
            (4, 0.3, -0.1, GROOVE_Z), (5, 0.3, -0.1, 0.25)]
    side = trace(keys, groove_side_force=lambda t: 2.5 if 2.5 <= t < 2.6 else 0.5)
    g = score(side, layout()).groove
    assert g.done and g.share == pytest.approx(1.0) and g.left_at is None and g.reached_exit
    assert "; in it to the exit;" in score(side, layout()).lines()[2]
    assert g.max_side_force_n == 2.5
    assert g.entered_at_s == pytest.approx(1 - 0.005 / 0.055, abs=0.002)  # z reaches the top 0.20
    assert g.done_at_s == pytest.approx(1 + 0.9 * 3, abs=0.002)  # 90 % of 0.3 m at 0.1 m/s from t 1 s


def test_groove_left_sideways_halfway_is_named_where():
    # along the first segment and half the second, then across it: out where |y| > 0.01 (half the width)
    keys = [(0, 0.4, 0.1, 0.25), (1, 0.4, 0.1, GROOVE_Z), (2, 0.4, 0.0, GROOVE_Z), (2.5, 0.35, 0.0, GROOVE_Z),
            (3.5, 0.35, 0.03, GROOVE_Z)]
    g = score(trace(keys), layout()).groove
    assert not g.done
    assert g.share == pytest.approx(0.15 / 0.3, abs=0.001)   # 0.1 m + 0.05 m of 0.3 m
    assert g.left_at == pytest.approx((0.35, 0.01), abs=0.0001)
    line = score(trace(keys), layout()).lines()[2]
    assert line.startswith("groove    FAIL  50 % of the path inside (needs 90 %); left at (0.350, 0.010) m")


def test_groove_stuck_inside_to_the_end_of_the_run_did_not_leave_it():
    keys = [(0, 0.4, 0.1, 0.25), (1, 0.4, 0.1, GROOVE_Z), (1.5, 0.4, 0.05, GROOVE_Z),
            (3, 0.4, 0.05, GROOVE_Z)]
    g = score(trace(keys), layout()).groove
    assert not g.done and g.left_at is None and not g.reached_exit
    assert g.share == pytest.approx(0.05 / 0.3, abs=0.001)
    assert "; still in it when the run ended;" in score(trace(keys), layout()).lines()[2]


def test_groove_above_its_top_or_through_its_floor_is_not_inside():
    above = trace([(0, 0.4, 0.1, 0.21), (3, 0.3, -0.1, 0.21)])
    assert score(above, layout()).groove.share == 0.0 and score(above, layout()).groove.entered_at_s is None
    floor = 0.2 - 0.01 - DEPTH_SLACK_M
    below = trace([(0, 0.4, 0.1, floor - 0.001), (1, 0.4, 0.0, floor - 0.001)])
    assert score(below, layout()).groove.entered_at_s is None


# -- the egg ------------------------------------------------------------------------------------

def ramp_hold(t, peak=800.0, hold=2.5):
    """0 -> peak over 1 s from t 1 s, held for ``hold`` s, then 0."""
    if t < 1:
        return 0.0
    if t < 2:
        return peak * (t - 1)
    return peak if t < 2 + hold else 0.0


def test_egg_held_in_the_band():
    log = trace([(0, 0.2, 0.2, 0.3), (6, 0.2, 0.2, 0.3)], scale_g=ramp_hold)
    e = score(log, layout()).egg
    # >= 500 g from t = 1 + 500/800 s to 4.5 s: 2.875 s; done 2 s after it entered the band
    assert e.done and not e.broken and e.peak_g == 800.0
    assert e.in_band_s == pytest.approx(2.875, abs=0.002)
    assert e.done_at_s == pytest.approx(1.625 + 2.0, abs=0.002)


def test_egg_too_short_too_hard_or_broken():
    still = [(0, 0, 0, 0.3), (6, 0, 0, 0.3)]
    short = score(trace(still, scale_g=lambda t: ramp_hold(t, hold=1.0)), layout()).egg
    assert not short.done and short.in_band_s == pytest.approx(1.375, abs=0.002)
    hard = score(trace(still, scale_g=lambda t: ramp_hold(t, peak=1200.0)), layout()).egg
    # in the band only on the ramp, 500..1000 g: 500/1200 s
    assert not hard.done and hard.peak_g == 1200.0 and hard.in_band_s == pytest.approx(500 / 1200, abs=0.002)
    # in the band for 3 s, then crushed at t 5 s: the egg is broken, the task not done
    crushed = trace([(0, 0, 0, 0.3), (6, 0, 0, 0.3)], scale_g=lambda t: 3000.0 if 5 <= t < 5.01 else
                    (700.0 if 2 <= t < 5 else 0.0), egg_broken=lambda t: 1.0 if t >= 5 else 0.0)
    e = score(crushed, layout()).egg
    assert e.broken and not e.done and e.broken_at_s == pytest.approx(5.0) and e.peak_g == 3000.0
    assert "BROKEN at t = 5.00 s" in score(crushed, layout()).lines()[3]


# -- the whole card -----------------------------------------------------------------------------

def full_run():
    """Every task done: still to 0.5 s, peg 1.5-2.5 s, over the obstacle at 3.25 s, the groove
    5-8 s, the egg pressed 9-12 s."""
    keys = [(0, 0.1, 0.1, 0.4), (0.5, 0.1, 0.1, 0.4), (1, 0, 0.3, 0.2), (1.5, 0, 0.3, 0.13),
            (2.5, 0, 0.3, 0.13), (3, 0, 0.3, 0.35), (3.25, 0.2, 0.1, 0.35), (3.5, 0.4, 0.1, 0.35),
            (4, 0.4, 0.1, 0.25), (5, 0.4, 0.1, GROOVE_Z),
            (6, 0.4, 0.0, GROOVE_Z), (7, 0.3, 0.0, GROOVE_Z), (8, 0.3, -0.1, GROOVE_Z), (8.5, 0.2, 0.2, 0.32),
            (13, 0.2, 0.2, 0.32)]
    return trace(keys, scale_g=lambda t: 700.0 if 9 <= t < 12 else 0.0)


def test_a_full_run_has_a_time_from_first_motion_to_last_task():
    card = score(full_run(), layout())
    assert card.done == 4
    # first motion: 5 mm from (0.1, 0.1, 0.4) after t 0.5 s, moving at |(-0.1, 0.2, -0.2)| / 0.5 s = 0.6 m/s
    assert card.first_motion_s == pytest.approx(0.5 + MOTION_M / 0.6, abs=0.002)
    # the last task is the egg: 2 s after 9 s
    assert card.egg.done_at_s == pytest.approx(11.0, abs=0.002)
    assert card.time_s == pytest.approx(11.0 - card.first_motion_s, abs=0.002)
    d = card.as_dict()
    assert set(d) == {"tasks", "time_s"} and list(d["tasks"]) == ["peg", "obstacle", "groove", "egg"]
    assert d["tasks"]["egg"] == {"done": True, "peak_g": 700.0, "in_band_s": 3.0, "broken": False}
    assert d["tasks"]["groove"]["left_at"] is None and d["tasks"]["obstacle"]["touched"] is False
    assert card.lines()[-1].startswith(f"time      {card.time_s:.2f} s from the first motion")


def test_no_time_unless_all_four_are_done():
    log = full_run()
    log["egg_broken"][12000:] = 1.0
    card = score(log, layout())
    assert card.done == 3 and card.time_s is None and card.as_dict()["time_s"] is None
    assert card.lines()[-1] == "time      none: 3 of 4 tasks done"


def test_a_world_without_fixtures_scores_nothing_and_says_why():
    card = score(full_run(), layout(hole=1, obstacle=1, groove=1, egg=1))
    assert card.done == 0 and card.rules == layout().contest
    assert card.lines()[0] == "peg       FAIL  world 'hand' has no hole"
    assert card.lines()[3] == "egg       FAIL  world 'hand' has no egg"


def test_a_log_without_the_worlds_signals_is_one_line():
    log = full_run()
    del log["scale_g"]
    with pytest.raises(ScorecardError) as err:
        score(log, layout())
    assert "\n" not in str(err.value) and "'scale_g'" in str(err.value)


def test_the_contest_world_s_own_layout_and_rules():
    """The same rules read from crslab/worlds/contest.toml: down the hole's axis to 3 cm below its
    top, held 1 s; the rules ask 5 mm for 0.5 s (its [contest] table: crslab's defaults)."""
    from crslab.world import load_world

    world = load_world("contest")
    (x, y), top = world.hole.center_xy_m, world.hole.top_z_m
    log = trace([(0, x, y, top + 0.05), (1, x, y, top - 0.03), (2, x, y, top - 0.03), (3, x, y, top + 0.05)])
    card = score(log, world)
    assert card.rules == ContestRules(band_g=(500.0, 1000.0), hold_s=2.0, hold_tolerance_s=0.2,
                                      peg_min_depth_m=0.005, peg_hold_s=0.5, groove_min_share=0.9,
                                      obstacle_around=True) == ContestRules()
    assert card.peg.done and card.peg.depth_m == pytest.approx(0.03)
    # at least 5 mm deep from 11/16 of the way down (t = 0.6875 s) to 5/16 of the way up (t = 2.3125 s)
    assert card.peg.held_s == pytest.approx(1.625, abs=0.002)
    assert not card.egg.done and card.egg.note == "" and not card.obstacle.passed_over
