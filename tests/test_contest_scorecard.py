"""The contest's scorecard on hand-made scope logs: each expected score and reason is worked out by
hand from the trace's keyframes (1 ms rows) and the small layout below, not by the scorecard's
code. The world's own columns (the peg's depth, the groove's nearest point, the forces on each
fixture, how the egg broke) are what the C world writes; here the trace writes them from the
keyframes' geometry, so each test says what the world measured and checks what the card makes
of it."""

from types import SimpleNamespace

import numpy as np
import pytest

from crslab.contest.motion import MOTION_M, STILL_S
from crslab.contest.offsets import Rest
from crslab.contest.scorecard import RunFacts, ScorecardError, score
from crslab.run.status import RunStatus
from crslab.worker.run_stats import RunStats

MS = 0.001
RULES = dict(band_g=(500.0, 1000.0), hold_s=2.0, hold_tolerance_s=0.2, peg_min_depth_m=0.005, peg_hold_s=0.5,
             groove_min_share=0.9, obstacle_around=True)
CORNERS = ((0.4, 0.1), (0.4, 0.0), (0.3, 0.0), (0.3, -0.1))


def layout(*missing, **rules):
    """A small contest layout: the hole at (0, 0.3) with its top at z 0.15 (2 cm wide); an obstacle
    4 x 4 x 10 cm centred at (0.2, 0.1, 0.25) (top z 0.30); a Z groove of three 10 cm segments
    (0.4, 0.1) -> (0.4, 0) -> (0.3, 0) -> (0.3, -0.1), top z 0.20, 2 cm wide, 1 cm deep; an egg
    4 cm across at (0.2, 0.2), its top at z 0.30."""
    world = SimpleNamespace(
        name="hand",
        hole=SimpleNamespace(center_xy_m=(0.0, 0.3), top_z_m=0.15, diameter_m=0.02, depth_m=0.04),
        obstacle=SimpleNamespace(center_xy_m=(0.2, 0.1), top_z_m=0.3, size_xy_m=(0.04, 0.04)),
        groove=SimpleNamespace(corners_xy_m=CORNERS, top_z_m=0.2, width_m=0.02, depth_m=0.01),
        egg=SimpleNamespace(center_xy_m=(0.2, 0.2), top_z_m=0.3, diameter_m=0.04),
        contest=SimpleNamespace(**{**RULES, **rules}),
    )
    for k in missing:
        setattr(world, k, None)
    return world


def along_the_z(xy):
    """The Z's nearest point to each x-y point: (distance from the centre line, length along it
    from the entrance). The three legs are axis-aligned: legs 1 and 3 run along -y at x 0.4 and
    0.3, leg 2 along -x at y 0."""
    out = []
    for x, y in xy:
        legs = [(abs(x - 0.4) if 0.0 <= y <= 0.1 else np.hypot(x - 0.4, y - np.clip(y, 0.0, 0.1)),
                 0.1 - np.clip(y, 0.0, 0.1)),
                (np.hypot(x - np.clip(x, 0.3, 0.4), y), 0.1 + 0.4 - np.clip(x, 0.3, 0.4)),
                (np.hypot(x - 0.3, y - np.clip(y, -0.1, 0.0)), 0.2 - np.clip(y, -0.1, 0.0))]
        out.append(min(legs))
    return np.asarray(out)


def trace(keys, world=None, **signals):
    """A scope log at 1 ms from keyframes ``[(t_s, x, y, z), ...]`` (linear between them) and
    ``signals``: name -> function of t (s) or constant (0 when not given). The peg's depth and the
    groove's nearest point are the world's measures of the tip."""
    world = world or layout()
    keys = np.asarray(keys, float)
    tick = np.arange(0, int(round(keys[-1, 0] * 1000)) + 1)
    t = tick * MS
    tip = np.stack([np.interp(t, keys[:, 0], keys[:, k]) for k in (1, 2, 3)], axis=1)
    log = {"tick": tick[:, None].astype(np.int64), "peg_tip": tip}
    hole = world.hole
    inside = np.hypot(tip[:, 0] - 0.0, tip[:, 1] - 0.3) <= 0.01
    log["peg_depth"] = np.where(inside, np.maximum(0.15 - tip[:, 2], 0.0), 0.0)[:, None] if hole else \
        np.zeros((len(t), 1))
    near = along_the_z(tip[:, :2])
    log["groove_offset"], log["groove_along"] = near[:, :1], near[:, 1:]
    parts = ("obstacle_peg_force", "obstacle_forearm_force", "obstacle_upper_arm_force")
    for name in ("egg_force", "scale_g", "egg_broken", "egg_broken_by", "hole_force", *parts,
                 "groove_side_force", "groove_force", "table_force", "safety", "motor_board_off"):
        f = signals.get(name, 0.0)
        values = np.asarray([f(v) for v in t], float) if callable(f) else np.full(len(t), float(f))
        log[name] = values[:, None]
    log["obstacle_force"] = sum(log[p] for p in parts)
    return log


# -- the peg ------------------------------------------------------------------------------------

def test_peg_in_the_hole_deep_enough_long_enough():
    # down the hole's axis from z 0.20 (t 1 s) to 0.13 (t 2 s: 2 cm below the top), held to 3 s,
    # up again to 0.20 at 4 s. At least 5 mm deep means z <= 0.145: from t = 1 + 0.055/0.07 s to
    # 3 + 0.015/0.07 s; done 0.3 s after it got there (the rules' 0.5 s less the TA's 0.2 s).
    log = trace([(0, 0, 0.3, 0.2), (1, 0, 0.3, 0.2), (2, 0, 0.3, 0.13), (3, 0, 0.3, 0.13), (4, 0, 0.3, 0.2)])
    card = score(log, layout())
    assert card.peg.done and card.peg.stopped_at is None
    assert card.peg.depth_m == pytest.approx(0.02, abs=1e-9)
    assert card.peg.held_s == pytest.approx((3 + 0.015 / 0.07) - (1 + 0.055 / 0.07), abs=0.002)
    assert card.peg.done_at_s == pytest.approx(1 + 0.055 / 0.07 + 0.3, abs=0.002)


def test_a_peg_that_misses_the_hole_says_where_it_stopped():
    # down 15 mm off the axis (outside the 10 mm radius) to 2 mm above the block's top, where it stays
    card = score(trace([(0, 0.015, 0.3, 0.2), (1, 0.015, 0.3, 0.152), (3, 0.015, 0.3, 0.152)]), layout())
    p = card.peg
    assert (p.done, p.depth_m, p.held_s) == (False, 0.0, 0.0)
    assert p.off_axis_m == pytest.approx(0.015) and p.above_top_m == pytest.approx(0.002)
    assert p.stopped_at == pytest.approx((0.015, 0.3, 0.152))
    assert card.lines()[0] == ("peg       FAIL  0.0 mm deep at most, held 0.00 s (needs 5 mm for 0.50 s; "
                               "a TA allows 0.30 s); it stopped 15 mm from the hole's axis, 2 mm above the "
                               "hole's top, at (0.015, 0.300, 0.152) m")
    # one that never comes near the hole says how near it came
    far = score(trace([(0, 0.1, 0.3, 0.2), (1, 0.1, 0.3, 0.1)]), layout()).lines()[0]
    assert far.endswith("it never came within 30 mm of the hole's axis (nearest 100 mm, at (0.100, 0.300, "
                        "0.100) m)")


def test_a_short_stay_is_not_enough():
    # in the hole, 1.5 cm deep from t 0.5 to 0.6 s; at least 5 mm (z <= 0.145) from 0.5 * 0.055/0.065 s
    # on the way down to 0.6 + 0.5 * 0.01/0.065 s on the way up: 0.254 s, short of the 0.3 s a TA
    # allows of the rules' 0.5 s
    short = trace([(0, 0, 0.3, 0.2), (0.5, 0, 0.3, 0.135), (0.6, 0, 0.3, 0.135), (1.1, 0, 0.3, 0.2)])
    card = score(short, layout())
    held = 0.6 + 0.5 * 0.01 / 0.065 - 0.5 * 0.055 / 0.065
    assert not card.peg.done and card.peg.held_s == pytest.approx(held, abs=0.002)
    assert card.peg.off_axis_m == 0.0 and card.peg.above_top_m == pytest.approx(-0.015)
    assert "it stopped 0 mm from the hole's axis, 15 mm below the hole's top" in card.lines()[0]


@pytest.mark.parametrize("rows, done", [(300, True), (299, False)])
def test_a_ta_allows_the_peg_s_stay_a_little_short_of_half_a_second(rows, done):
    # down the axis in 1 ms from z 0.20 to 0.135 (15 mm deep) at t 0.101 s, held there for exactly
    # `rows` rows (1 ms each), up again in 1 ms: the rules' 0.5 s less the TA's 0.2 s is 300 rows
    end = 0.101 + (rows - 1) * MS
    card = score(trace([(0, 0, 0.3, 0.2), (0.1, 0, 0.3, 0.2), (0.101, 0, 0.3, 0.135), (end, 0, 0.3, 0.135),
                        (end + MS, 0, 0.3, 0.2), (1.0, 0, 0.3, 0.2)]), layout())
    assert card.peg.done is done and card.peg.held_s == pytest.approx(rows * MS, abs=1e-9)
    if done:
        assert card.peg.done_at_s == pytest.approx(0.101 + 0.299, abs=1e-9)


# -- the obstacle -------------------------------------------------------------------------------

# from the hole (0, 0.3) towards the groove's entrance (0.4, 0.1): the obstacle's line is across
# that way, through its centre (0.2, 0.1)
HOLE_TO_GROOVE_OVER = [(0, 0, 0.3, 0.35), (1, 0.2, 0.1, 0.35), (2, 0.4, 0.1, 0.35)]


def test_passed_over_untouched():
    o = score(trace(HOLE_TO_GROOVE_OVER), layout()).obstacle
    assert o.done and o.passed == "over" and not o.touched
    # it crosses the line when it is at the obstacle's centre, at t = 1 s
    assert o.done_at_s == pytest.approx(1.0, abs=0.002)
    assert o.passed_at == pytest.approx((0.2, 0.1, 0.35), abs=3e-4)


def test_a_touch_names_the_part_of_the_arm():
    log = trace(HOLE_TO_GROOVE_OVER, obstacle_forearm_force=lambda t: 30.0 if 0.9 <= t < 1.1 else 0.0,
                obstacle_upper_arm_force=lambda t: 4.0 if 1.0 <= t < 1.05 else 0.0)
    card = score(log, layout())
    o = card.obstacle
    assert not o.done and [x.part for x in o.touches] == ["forearm", "upper arm"]
    assert o.touches[0].first_s == pytest.approx(0.9) and o.touches[0].max_force_n == 30.0
    assert o.max_force_n == 34.0   # both at once, 1.0 to 1.05 s
    assert card.lines()[1].startswith("obstacle  FAIL  touched by the forearm at t = 0.90 s (up to 30.0 N), "
                                      "the upper arm at t = 1.00 s (up to 4.0 N); passed over it")
    assert card.as_dict()["tasks"]["obstacle"]["touched_by"] == ["forearm", "upper arm"]
    # a force at the threshold (0.05 N, the world's) is no touch; just above it is
    assert not score(trace(HOLE_TO_GROOVE_OVER, obstacle_peg_force=0.05), layout()).obstacle.touched
    assert score(trace(HOLE_TO_GROOVE_OVER, obstacle_peg_force=0.0501), layout()).obstacle.touched


def test_around_the_obstacle_counts_when_the_rules_allow_it():
    # beside it: from the hole to (0.2, 0.2) and on to the entrance, at z 0.25 (below its top): the
    # line is crossed at the obstacle's centre's projection; the tip there is 0.1 m from its
    # centre across the way ... computed: crossing point where (p - c) . way = 0
    way = np.array([0.4, -0.2]) / np.hypot(0.4, -0.2)
    keys = [(0, 0, 0.3, 0.25), (1, 0.2, 0.2, 0.25), (2, 0.4, 0.1, 0.25)]
    # on the first leg p = (0.2 s, 0.3 - 0.1 s): (p - c) . way = 0 at s with
    # 0.4 (0.2 s - 0.2) - 0.2 (0.2 - 0.1 s) = 0
    s = (0.08 + 0.04) / (0.08 + 0.02)
    crossing = np.array([0.2 * s, 0.3 - 0.1 * s])
    assert abs((crossing - (0.2, 0.1)) @ way) < 1e-12
    beside = np.hypot(max(abs(crossing[0] - 0.2) - 0.02, 0), max(abs(crossing[1] - 0.1) - 0.02, 0))
    o = score(trace(keys), layout()).obstacle
    assert o.done and o.passed == "around" and o.beside_m == pytest.approx(beside, abs=3e-4)
    assert score(trace(keys), layout()).lines()[1].startswith(
        f"obstacle  done  not touched; passed around it, {1000 * beside:.0f} mm from its side")
    strict = score(trace(keys), layout(obstacle_around=False)).obstacle
    assert not strict.done and strict.passed is None


def test_never_passing_it_is_not_done_even_untouched():
    o = score(trace([(0, 0, 0.3, 0.35), (1, 0.05, 0.25, 0.35)]), layout()).obstacle
    assert not o.done and o.passed is None
    assert score(trace([(0, 0, 0.3, 0.35), (1, 0.05, 0.25, 0.35)]), layout()).lines()[1] == \
        "obstacle  FAIL  not touched; never passed it on the way from the hole to the groove"


# -- the groove ---------------------------------------------------------------------------------

GROOVE_Z = 0.195   # 5 mm below the plate's top, in the groove


def test_groove_followed_corner_to_corner():
    keys = [(0, 0.4, 0.1, 0.25), (1, 0.4, 0.1, GROOVE_Z), (2, 0.4, 0.0, GROOVE_Z), (3, 0.3, 0.0, GROOVE_Z),
            (4, 0.3, -0.1, GROOVE_Z), (5, 0.3, -0.1, 0.25)]
    card = score(trace(keys, groove_side_force=lambda t: 2.5 if 2.5 <= t < 2.6 else 0.5), layout())
    g = card.groove
    assert g.done and g.share == pytest.approx(1.0) and g.left_at is None and g.reached_exit
    assert "; in it to the exit;" in card.lines()[2] and g.max_side_force_n == 2.5
    assert g.entered_at_s == pytest.approx(1 - 0.005 / 0.055, abs=0.002)  # z reaches the top 0.20
    assert g.done_at_s == pytest.approx(1 + 0.9 * 3, abs=0.002)  # 90 % of 0.3 m at 0.1 m/s from t 1 s


def test_groove_left_sideways_halfway_is_named_where():
    # along the first segment and half the second, then across it: out where |y| > 0.01 (half the width)
    keys = [(0, 0.4, 0.1, 0.25), (1, 0.4, 0.1, GROOVE_Z), (2, 0.4, 0.0, GROOVE_Z), (2.5, 0.35, 0.0, GROOVE_Z),
            (3.5, 0.35, 0.03, GROOVE_Z)]
    card = score(trace(keys), layout())
    g = card.groove
    assert not g.done and g.share == pytest.approx(0.15 / 0.3, abs=0.001)   # 0.1 m + 0.05 m of 0.3 m
    assert g.left_at == pytest.approx((0.35, 0.01), abs=0.0001)
    assert card.lines()[2].startswith("groove    FAIL  50 % of the path inside (needs 90 %); left at "
                                      "(0.350, 0.010) m")


def test_a_brush_of_the_channel_s_edge_on_the_plate_before_dropping_in_is_not_the_stay():
    """A slanted entry slides on the plate's top (its z, 0.20) along the entrance's edge, within
    half the width of the centre line for 7 ms, out again (11 mm off), then drops in 10 mm along and
    follows the Z to the exit: the stay that covers the Z is the one scored."""
    keys = [(0, 0.43, 0.1, 0.25), (0.5, 0.415, 0.1, 0.2), (0.7, 0.4099, 0.1, 0.2), (0.702, 0.4099, 0.1, 0.2),
            (0.72, 0.412, 0.1, 0.2), (0.8, 0.411, 0.09, 0.2), (1, 0.4, 0.09, GROOVE_Z),
            (1.9, 0.4, 0.0, GROOVE_Z), (2.9, 0.3, 0.0, GROOVE_Z), (3.9, 0.3, -0.1, GROOVE_Z),
            (4.4, 0.3, -0.1, 0.25)]
    log = trace(keys)
    inside = (log["groove_offset"][:, 0] <= 0.01) & (log["peg_tip"][:, 2] <= 0.2)
    brush = np.flatnonzero(inside[:800])
    assert 1 <= len(brush) <= 10 and not inside[750]  # in for a few ms at the edge, then out again
    g = score(log, layout()).groove
    assert g.done and g.reached_exit and g.left_at is None
    assert g.share == pytest.approx(0.29 / 0.3, abs=0.002)  # from 10 mm along to the exit
    assert g.entered_at_s > 0.8


def test_a_peg_stuck_in_the_groove_says_where_it_stayed():
    # in at the entrance at t 1 s, 5 cm along by 1.5 s, then still there to 3 s
    keys = [(0, 0.4, 0.1, 0.25), (1, 0.4, 0.1, GROOVE_Z), (1.5, 0.4, 0.05, GROOVE_Z),
            (3, 0.4, 0.05, GROOVE_Z)]
    card = score(trace(keys), layout())
    g = card.groove
    assert not g.done and g.left_at is None and not g.reached_exit
    assert g.share == pytest.approx(0.05 / 0.3, abs=0.001)
    # still (within 2 mm) from when it was 2 mm short of (0.4, 0.05): 1.5 - 0.002 / 0.1 s
    assert g.stuck_at == pytest.approx((0.4, 0.05)) and g.stuck_from_s == pytest.approx(1.48, abs=0.26)
    assert "; still in it when the run ended; it stayed at (0.400, 0.050) m from t = " in card.lines()[2]


def test_a_peg_that_never_goes_below_the_plate_s_top_says_how_high_it_stayed():
    # along the Z's first leg 6 mm above the plate's top, never in it
    card = score(trace([(0, 0.4, 0.1, 0.21), (1, 0.4, 0.0, 0.206), (2, 0.3, 0.0, 0.206)]), layout())
    g = card.groove
    assert g.share == 0.0 and g.entered_at_s is None and g.lowest_above_top_m == pytest.approx(0.006)
    assert "never below the plate's top over it: the tip's lowest over the channel 6.0 mm above the top" \
        in card.lines()[2]
    away = score(trace([(0, 0.1, 0.1, 0.19), (1, 0.1, 0.0, 0.19)]), layout()).lines()[2]
    assert "never over the channel: 200 mm from its centre line at the nearest" in away


# -- the egg ------------------------------------------------------------------------------------

def ramp_hold(t, peak=800.0, hold=2.5):
    """0 -> peak over 1 s from t 1 s, held for ``hold`` s, then 0."""
    if t < 1:
        return 0.0
    if t < 2:
        return peak * (t - 1)
    return peak if t < 2 + hold else 0.0


OVER_THE_EGG = [(0, 0.2, 0.2, 0.3), (6, 0.2, 0.2, 0.3)]


def test_egg_held_in_the_band():
    e = score(trace(OVER_THE_EGG, scale_g=ramp_hold, egg_force=1.0), layout()).egg
    # >= 500 g from t = 1 + 500/800 s to 4.5 s: 2.875 s; done 1.8 s (2 s less a TA's 0.2 s) after it entered
    assert e.done and not e.broken and e.peak_g == 800.0
    assert e.in_band_s == pytest.approx(2.875, abs=0.002)
    assert e.done_at_s == pytest.approx(1.625 + 1.8, abs=0.002)


def test_a_ta_allows_a_press_a_little_short_of_two_seconds():
    # in the band from 1.625 s (500 g on the ramp) to 2 s + the hold: for 1.91 s (a real team's): done;
    # for 1.7 s: not
    for in_band, done in ((1.91, True), (1.7, False)):
        hold = in_band - 0.375
        log = trace(OVER_THE_EGG, scale_g=lambda t, h=hold: ramp_hold(t, hold=h), egg_force=1.0)
        e = score(log, layout()).egg
        assert e.done is done and e.in_band_s == pytest.approx(in_band, abs=0.002)
    line = score(trace(OVER_THE_EGG, scale_g=ramp_hold, egg_force=1.0), layout()).lines()[3]
    assert "(needs 2.00 s; a TA allows 1.80 s)" in line


def test_a_broken_egg_says_what_broke_it_and_the_press_s_peak_before():
    # in the band at 700 g from 2 s, then the press goes on up to 1500 g at 5 s, where it breaks
    def grams(t):
        return 0.0 if t < 2 else 700.0 if t < 4 else 700.0 + 800.0 * (t - 4) if t < 5 else 2500.0

    crushed = trace(OVER_THE_EGG, scale_g=grams, egg_force=1.0, egg_broken=lambda t: 1.0 if t >= 5 else 0.0,
                    egg_broken_by=lambda t: 1.0 if t >= 5 else 0.0)
    card = score(crushed, layout())
    e = card.egg
    assert e.broken and not e.done and e.broken_at_s == pytest.approx(5.0) and e.broken_by == "the press"
    assert e.peak_before_break_g == pytest.approx(700.0 + 800.0 * 0.999, abs=0.01)  # the row before 5 s
    assert "BROKEN at t = 5.00 s by the press, the press's peak before it 1499 g" in card.lines()[3]
    side = trace(OVER_THE_EGG, egg_force=1.0, egg_broken=lambda t: 1.0 if t >= 3 else 0.0,
                 egg_broken_by=lambda t: 2.0 if t >= 3 else 0.0)
    assert score(side, layout()).egg.broken_by == "a side hit"


def test_the_egg_line_says_when_it_was_first_touched_and_how_fast():
    """The egg's force passes the touch's threshold at t = 2 s, the world row's touch speed (held
    from the contact's start) 36 mm/s then; a log without the touch-speed column gives the time
    alone; an egg never touched has neither."""
    def force(t):
        return 0.0 if t < 2.0 else 6.0

    log = trace(OVER_THE_EGG, scale_g=lambda t: force(t) / 9.80665 * 1000, egg_force=force)
    log["egg_touch_speed"] = np.where(log["egg_force"] > 0, 0.036, 0.0)
    card = score(log, layout())
    assert card.egg.touched_at_s == pytest.approx(2.0) and card.egg.touch_speed_m_s == pytest.approx(0.036)
    assert card.lines()[3].endswith("; not broken; first touched at t = 2.00 s coming down at 36 mm/s")
    egg = card.as_dict()["tasks"]["egg"]
    assert egg["touched_at_s"] == 2.0 and egg["touch_speed_m_s"] == 0.036
    del log["egg_touch_speed"]
    assert score(log, layout()).lines()[3].endswith("; first touched at t = 2.00 s")
    never = score(trace([(0, 0.2, 0.2, 0.35), (1, 0.2, 0.2, 0.314)]), layout())
    assert never.egg.touched_at_s is None and "first touched" not in never.lines()[3]


def test_an_egg_never_touched_says_how_high_the_peg_stayed():
    card = score(trace([(0, 0.2, 0.2, 0.35), (1, 0.2, 0.2, 0.314)]), layout())
    assert not card.egg.touched and card.egg.lowest_above_top_m == pytest.approx(0.014)
    assert card.lines()[3].endswith("never touched: the tip's lowest over it 14.0 mm above its top")


def test_an_arm_at_rest_over_the_egg_says_the_push_its_static_friction_holds():
    """Down to 14 mm over the egg at t = 1 s, still there to 3 s: the card says when it rested and
    the push down at the tip the joints' static friction holds there, computed here from two inverse
    kinematics 0.1 mm apart (the scorecard solves the Jacobian) and the plant's static bands."""
    from crslab import crs
    from crslab.plant.plant_params import PlantParams

    tip_m = np.array([0.2, 0.2, 0.314])
    log = trace([(0, 0.2, 0.2, 0.35), (1, *tip_m), (3, *tip_m)])
    log["qpos_dh_rad"] = crs.ik_dh(log["peg_tip"] / 0.0254)
    card = score(log, layout())
    dz_m = 1e-4
    turn = (crs.ik((tip_m - [0, 0, dz_m]) / 0.0254) - crs.ik(tip_m / 0.0254)) / dz_m  # rad per m down
    plant = PlantParams.defaults()
    expected = sum((plant.static_band_nm(m)[1] if w > 0 else -plant.static_band_nm(m)[0]) * abs(w)
                   for m, w in zip((1, 2, 3), turn))
    e = card.egg
    assert not e.done and e.done_at_s is None
    assert e.breakaway_n == pytest.approx(expected, rel=1e-3)
    # within 0.5 mm of where it stopped from 0.5 mm before it, coming down 36 mm in the second
    assert e.rested_from_s == pytest.approx(1 - 0.5 / 36, abs=0.002)
    assert e.rested_for_s == pytest.approx(2 + 0.5 / 36, abs=0.002)
    assert card.lines()[3].endswith(
        f"14.0 mm above its top; the arm rested there from t = 0.99 s for 2.0 s: from rest at that pose its "
        f"joints' static friction holds it against a push down at the tip under about {expected:.0f} N")
    # still for less than half a second: no rest, no figure
    moving = trace([(0, 0.2, 0.2, 0.35), (1, *tip_m), (1.4, *tip_m), (2, 0.2, 0.2, 0.35)])
    moving["qpos_dh_rad"] = crs.ik_dh(moving["peg_tip"] / 0.0254)
    assert score(moving, layout()).egg.breakaway_n is None


# -- the whole card -----------------------------------------------------------------------------

def full_run(end=13.0):
    """Every task done: still to 0.5 s, peg 1.5-2.5 s, over the obstacle at 3.25 s, the groove
    5-8 s, the egg pressed 9-12 s, still over the egg from 8.5 s to ``end``."""
    keys = [(0, 0.1, 0.1, 0.4), (0.5, 0.1, 0.1, 0.4), (1, 0, 0.3, 0.2), (1.5, 0, 0.3, 0.13),
            (2.5, 0, 0.3, 0.13), (3, 0, 0.3, 0.35), (3.25, 0.2, 0.1, 0.35), (3.5, 0.4, 0.1, 0.35),
            (4, 0.4, 0.1, 0.25), (5, 0.4, 0.1, GROOVE_Z),
            (6, 0.4, 0.0, GROOVE_Z), (7, 0.3, 0.0, GROOVE_Z), (8, 0.3, -0.1, GROOVE_Z), (8.5, 0.2, 0.2, 0.32),
            (end, 0.2, 0.2, 0.32)]
    return trace(keys, scale_g=lambda t: 700.0 if 9 <= t < 12 else 0.0, egg_force=1.0)


def test_a_full_run_has_a_time_from_first_motion_to_last_task():
    card = score(full_run(), layout())
    assert card.complete and card.done == 4
    # first motion: 5 mm from (0.1, 0.1, 0.4) after t 0.5 s, moving at |(-0.1, 0.2, -0.2)| / 0.5 s = 0.6 m/s
    assert card.first_motion_s == pytest.approx(0.5 + MOTION_M / 0.6, abs=0.002)
    # the last task is the egg: 1.8 s after 9 s
    assert card.egg.done_at_s == pytest.approx(10.8, abs=0.002)
    assert card.time_s == pytest.approx(10.8 - card.first_motion_s, abs=0.002)
    d = card.as_dict()
    assert d["complete"] is True and list(d["tasks"]) == ["peg", "obstacle", "groove", "egg"]
    assert d["tasks"]["egg"]["in_band_s"] == 3.0 and d["tasks"]["egg"]["broken_by"] is None
    assert card.lines()[4].startswith(f"time      {card.time_s:.2f} s from the first motion")
    # still over the egg from 8.5 s: the arm at rest since then, 4.5 s before the end: not yet for
    # good (10 s); run to 19 s, it is
    assert card.ended.still_since_s is None and card.lines()[-1] == "run       ended at t = 13.00 s"
    # (within 2 mm of its end from 2 mm before it, at |(-0.1, 0.3, 0.125)| / 0.5 s)
    speed = np.linalg.norm([-0.1, 0.3, 0.125]) / 0.5
    still = score(full_run(19.0), layout()).ended.still_since_s
    assert still == pytest.approx(8.5 - 0.002 / speed, abs=0.0015)
    assert 19.0 - 8.5 >= STILL_S > 18.0 - 8.5
    assert score(full_run(18.0), layout()).ended.still_since_s is None


def test_no_time_unless_all_four_are_done():
    log = full_run()
    log["egg_broken"][12000:] = 1.0
    log["egg_broken_by"][12000:] = 1.0
    card = score(log, layout())
    assert card.done == 3 and not card.complete and card.time_s is None and card.as_dict()["time_s"] is None
    assert card.lines()[4] == "time      none: 3 of 4 tasks done"


def test_the_run_s_lines_say_where_it_rested_and_what_cut_it_short():
    log = full_run()
    log["safety"][7000:] = 1.0
    log["motor_board_off"][9500:] = 1.0
    stats = RunStats(over_budget=3, first_over_tick=(5123, 6000, 7000), motor_board_events=((9500, 2, True),))
    run = RunFacts(RunStatus.CRASHED, "final.c used a NULL pointer at final.c:99 in lab() at tick 13000",
                   13000, stats, Rest((0.0, -0.4, 0.26), "lab"), startup_ticks=4100)
    lines = score(log, layout(), run).lines()
    assert lines[5] == ("rest      -0.4000 0.2600 rad: the lab's own offset_Enc2_rad, offset_Enc3_rad (a lab "
                        "is calibrated to its bench)")
    assert lines[6] == ("run       crashed at t = 13.000 s: final.c used a NULL pointer at final.c:99 in "
                        "lab() at tick 13000; the card covers the run up to t = 13.000 s")
    assert lines[7] == ("safety    the arm left the safety envelope at t = 7.00 s: the framework's hold took "
                        "over from the lab and kept the arm to the end of the run: the lab's torques were "
                        "not used again")
    assert lines[8] == ("motors    the motor board cut every output at t = 9.50 s (joint 2 commanded over "
                        "its limit)")
    assert lines[9] == ("budget    3 lab() calls over the budget (the first at t = 5.123 s): on the board "
                        "they would miss their ticks")
    # before lab()'s first call the safety flag is the framework's own, not the lab's doing
    log["safety"][:] = 0.0
    log["safety"][1000:2000] = 1.0
    assert not any(x.startswith("safety") for x in score(log, layout(), run).lines())


def test_the_safety_line_names_the_limit_crossed_and_whether_the_arm_came_back():
    """The lab's own angles at the trip: the elbow (th3 DH = motor 3 - motor 2 + 90 deg) 0.5 deg
    past its 2.3 rad; the flag clear again 1 s later."""
    log = full_run()
    n = len(log["tick"])
    rest = np.array([0.0, -0.42, 0.24])
    enc = np.tile(rest, (n, 1))
    over = 2.3 + np.radians(0.5) - np.pi / 2 + rest[1]  # motor 3 that puts th3 DH 0.5 deg past 2.3 rad
    enc[7000:8000, 2] = over
    log["enc_rad"] = enc
    log["safety"][7000:8000] = 1.0
    line = next(x for x in score(log, layout()).lines() if x.startswith("safety"))
    assert line == ("safety    the arm left the safety envelope at t = 7.00 s (th3 DH = "
                    f"{np.degrees(2.3) + 0.5:.2f} deg is outside [8.59, 131.78] deg): the framework's hold "
                    "took over from the lab; the arm back inside at t = 8.00 s")
    run = score(log, layout()).as_dict()["run"]
    assert run["safety_back_s"] == 8.0 and run["safety_why"].startswith("th3 DH = 132.28 deg")


def test_the_safety_line_names_the_motors_the_lab_drove_at_the_clamp_just_before():
    """A kick: the lab's first calls command motor 2 at -40 (beyond the clamp) and motor 3 at +5
    (the clamp) for 15 ms from t = 4.1 s, the elbow past 2.3 rad 25 ms later; motor 1 at 4.99,
    under the clamp. A clamp 0.2 s before the trip, out of the card's 0.1 s, is not named, and a
    trip with no command at the clamp (a path that grazes the limit) names no motor."""
    log = full_run()
    n = len(log["tick"])
    rest = np.array([0.0, -0.42, 0.24])
    enc = np.tile(rest, (n, 1))
    enc[4140:, 2] = 2.3 + np.radians(0.1) - np.pi / 2 + rest[1]
    log["enc_rad"] = enc
    log["safety"][4140:] = 1.0
    tau = np.zeros((n, 3))
    tau[3900:3910, 0] = 5.0  # 0.24 s before the trip: out of the window
    tau[4100:4115] = [4.99, -40.0, 5.0]
    log["tau_lab"] = tau
    card = score(log, layout())
    line = next(x for x in card.lines() if x.startswith("safety"))
    assert "deg); before it the lab commanded motors 2 and 3 at the clamp (5 units) from t = 4.100 s: the " \
           "framework's hold took over" in line, line
    run = card.as_dict()["run"]
    assert run["safety_clamped"] == [2, 3] and run["safety_clamped_from_s"] == 4.1
    tau[4100:4115, 2] = 0.0  # motor 2 alone
    assert "the lab commanded motor 2 at the clamp" in next(x for x in score(log, layout()).lines()
                                                            if x.startswith("safety"))
    tau[4100:4115] = 1.0  # a graze: nothing at the clamp
    graze = score(log, layout())
    assert "clamp" not in next(x for x in graze.lines() if x.startswith("safety"))
    assert graze.as_dict()["run"]["safety_clamped"] == []


def test_a_world_without_fixtures_scores_nothing_and_says_why():
    card = score(full_run(), layout("hole", "obstacle", "groove", "egg"))
    assert card.done == 0
    assert card.lines()[0] == "peg       FAIL  world 'hand' has no hole"
    assert card.lines()[3] == "egg       FAIL  world 'hand' has no egg"


def test_a_log_without_the_worlds_signals_is_one_line():
    log = full_run()
    del log["scale_g"]
    with pytest.raises(ScorecardError) as err:
        score(log, layout())
    assert "\n" not in str(err.value) and "'scale_g'" in str(err.value)


def test_the_card_s_json_in_docs_has_the_keys_the_card_writes():
    """docs/contest.md's example card.json: the same keys, task by task, as :meth:`Scorecard.as_dict`."""
    import json
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "contest.md").read_text()
    shown = json.loads(re.search(r'^(\{"complete".*?\}\})\n```', text, re.MULTILINE | re.DOTALL).group(1))
    written = score(full_run(), layout()).as_dict()
    assert list(shown) == list(written)
    for task in written["tasks"]:
        assert list(shown["tasks"][task]) == list(written["tasks"][task]), task
    assert list(shown["run"]) == list(written["run"])
