"""The ``push`` scenario event and the built-in ``lab4_push``: a force at the end effector.

Unit level: the Lab 4 frame's rotation against a hand-derived matrix; the square wave's sign at
every tick around its flips (the board's C, against the rule written out here); the joint
torques of the force against MuJoCo's own ``mj_applyFT`` at the site ``ee``; malformed push
tables give one line naming file, line and key.

Run level (tests/labs/lab4_impedance.c, a Lab 4 impedance lab with its gains as watched
variables): under ``lab4_push`` a lab that weakens world x gives way along x, at least 5 times
as far as along y and z, by F / Kp within 20 %, with Kp read from the lab file; the same in the
Lab 4 handout's rotated frame (thz = pi/3, N's y weak), measured along R's y axis; a push given
in that frame moves the lab along N's y by |F| / Kp. The scope log's ``push_force`` is the square
wave tick by tick, ``ee`` the course's forward kinematics of the plant's angles; the transcript
and the log are the same at --fast and in other chunks.
"""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import mujoco
import numpy as np
import pytest
from crslab._core import ffi, lib

from crslab import crs
from crslab.plant.model import load_model
from crslab.run.api import simulate
from crslab.scenario.lab_events import SetVariable
from crslab.scenario.load import ScenarioError, load_scenario, parse_scenario
from crslab.scenario.push_events import Push, lab4_frame_matrix

LABS = Path(__file__).parent / "labs"
LAB = LABS / "lab4_impedance.c"
S3 = math.sqrt(3.0)
PUSH_N = np.array([5.0, 5.0, 5.0])   # lab4_push's force, world frame
FIRST_PUSH_TICK, HALF_PERIOD_TICKS, PERIODS = 6000, 1000, 5


def lab_gains() -> dict[str, float]:
    """The lab file's watched gains and angles, read from its text."""
    return {m[1]: float(m[2]) for m in re.finditer(r"^float (K[PD][xyz]|th[zxy]) = ([-0-9.]+);",
                                                   LAB.read_text(), flags=re.MULTILINE)}


def half_swing(run, periods: int = PERIODS) -> np.ndarray:
    """How far the end effector moves (world frame, m) from the square wave's -F halves to its +F
    halves, over two: the mean of each half's last 300 ms (the lab has settled), over every period.
    Whatever the force does not cause (gravity's sag, the offsets) cancels."""
    tick, ee = run.log["tick"][:, 0], run.log["ee"]

    def settled(start: int) -> np.ndarray:
        rows = (tick >= start + HALF_PERIOD_TICKS - 300) & (tick < start + HALF_PERIOD_TICKS)
        assert rows.sum() == 300
        return ee[rows].mean(axis=0)

    starts = [FIRST_PUSH_TICK + 2 * HALF_PERIOD_TICKS * k for k in range(periods)]
    plus = np.mean([settled(s) for s in starts], axis=0)
    minus = np.mean([settled(s + HALF_PERIOD_TICKS) for s in starts], axis=0)
    return (plus - minus) / 2


def with_sets(scenario: str, values: dict[str, float]):
    """A scenario with the lab's watched variables written at tick 0 (before lab() first runs)."""
    sc = load_scenario(scenario)
    sets = tuple(SetVariable(tick=0, name=k, value=v) for k, v in values.items())
    return dataclasses.replace(sc, events=sets + sc.events)


# -- the frame ----------------------------------------------------------------------------------

def test_the_frame_is_rz_rx_ry_as_derived_by_hand():
    # thz = 60 deg alone: N's y axis is (-sin 60, cos 60, 0)
    r = lab4_frame_matrix(math.pi / 3, 0.0, 0.0)
    assert np.allclose(r @ [0, 1, 0], [-S3 / 2, 0.5, 0], atol=1e-15)
    # the handout's second case, thx = 30 deg, thy = 60 deg: Rx(a) Ry(b) =
    # [[cb, 0, sb], [sa sb, ca, -sa cb], [-ca sb, sa, ca cb]] with ca = sb = sqrt 3 / 2, sa = cb = 1/2
    by_hand = np.array([[0.5, 0.0, S3 / 2], [S3 / 4, S3 / 2, -0.25], [-0.75, 0.5, S3 / 4]])
    assert np.allclose(lab4_frame_matrix(0.0, math.pi / 6, math.pi / 3), by_hand, atol=1e-15)
    # all three: Rz(90 deg) takes (x, y, z) to (-y, x, z), rows of the hand-derived product swapped
    rz90 = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    assert np.allclose(lab4_frame_matrix(math.pi / 2, math.pi / 6, math.pi / 3), rz90 @ by_hand, atol=1e-15)


def test_a_force_given_in_frame_n_is_r_f_in_the_world():
    text = ('end = 20\n[[event]]\nat = 6\nkind = "push"\nforce_n = [0, 0, 5]\n'
            'frame_deg = {thx = 30, thy = 60}\nperiod = 2\nuntil = 12\n')
    start, end = parse_scenario(text, Path("s.toml")).events
    assert isinstance(start, Push) and start.tick == 6000 and start.half_period_ticks == 1000
    # N's z axis, the third column of the hand-derived matrix above, times 5 N
    assert np.allclose(start.force_n, [5 * S3 / 2, -1.25, 5 * S3 / 4], atol=1e-14)
    assert start.given_n == (0.0, 0.0, 5.0)
    assert end.tick == 12000 and end.ends and end.describe() == "push ends"
    rad = parse_scenario(text.replace("frame_deg = {thx = 30, thy = 60}",
                                      "frame_rad = {thx = 0.5235987755982988, thy = 1.0471975511965976}"),
                         Path("s.toml")).events[0]
    assert np.allclose(rad.force_n, start.force_n, atol=1e-14)
    world = parse_scenario(text.replace("frame_deg = {thx = 30, thy = 60}\n", ""), Path("s.toml")).events[0]
    assert world.force_n == (0.0, 0.0, 5.0) and world.frame_rad is None
    assert start.describe() == ("push (0, 0, 5) N in frame N (thz 0, thx 30, thy 60 deg) = "
                                "(4.33, -1.25, 2.165) N world at the end effector, "
                                "square wave: sign flips every 1 s")


PUSH = 'kind = "push"\nforce_n = [5, 5, 5]\n'
MALFORMED = [
    ('kind = "push"\n', "2: force_n: missing"),
    ('kind = "push"\nforce_n = [5, 5]\n', "5: force_n: must be a list of three numbers"),
    ('kind = "push"\nforce_n = 5\n', "5: force_n: must be a list of three numbers"),
    (PUSH + 'frame = {thz = 1}\n', "6: frame: unknown key"),
    (PUSH + 'frame_deg = 60\n', "6: frame_deg: must be a table of thz, thx, thy"),
    (PUSH + 'frame_deg = {thw = 60}\n', "6: frame_deg: unknown angle 'thw'"),
    (PUSH + 'frame_rad = {thz = "pi"}\n', "6: frame_rad: thz must be a number"),
    (PUSH + 'frame_rad = {thz = 1}\nframe_deg = {thz = 1}\n', "7: frame_deg: give frame_rad or frame_deg"),
    (PUSH + 'period = 0.003\n', "6: period: half of it must be a whole number of ms"),
    (PUSH + 'period = 0\n', "6: period: half of it must be a whole number of ms"),
    (PUSH + 'period = -2\n', "6: period: must be at least 0"),
    (PUSH + 'until = 4\n', "6: until: must be later than at"),
]


@pytest.mark.parametrize("body, expected", MALFORMED)
def test_a_malformed_push_is_one_error_naming_file_line_and_key(body, expected):
    with pytest.raises(ScenarioError) as err:
        parse_scenario("end = 30\n[[event]]\nat = 5\n" + body, Path("bad.toml"))
    message = str(err.value)
    assert message.startswith("bad.toml:" + expected), message
    assert "\n" not in message


# -- the board's C ------------------------------------------------------------------------------

def board_push(start: int, half: int, force=(1.0, -2.0, 3.0), active: int = 1):
    push = ffi.new("crs_push *")
    push.active, push.start_tick, push.half_period_ticks = active, start, half
    for k in range(3):
        push.force_n[k] = force[k]
    return push


def force_at(push, tick: int) -> list[float]:
    out = ffi.new("double[3]")
    lib.crs_push_force(push, tick, out)
    return list(out)


def test_the_square_wave_flips_sign_at_every_half_period_counted_from_its_start():
    push = board_push(6000, 1000)
    f = [1.0, -2.0, 3.0]
    minus = [-v for v in f]
    zero = [0.0, 0.0, 0.0]
    assert force_at(push, 5999) == zero          # not yet
    assert [force_at(push, t) for t in (6000, 6999, 7000, 7999, 8000, 9999, 10_000)] == [
        f, f, minus, minus, f, minus, f]
    # every tick of three periods of an odd half period, against the rule: + in even halves
    push = board_push(123, 7)
    for tick in range(123, 123 + 6 * 7):
        sign = 1.0 if ((tick - 123) // 7) % 2 == 0 else -1.0
        assert force_at(push, tick) == [sign * v for v in f], tick
    assert force_at(board_push(100, 0), 10**9) == f       # constant
    assert force_at(board_push(100, 1000, active=0), 500) == zero


def test_the_push_reaches_the_joints_as_mujoco_applies_a_force_at_the_site_ee():
    model = load_model()
    data = mujoco.MjData(model)
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, "ee")
    body = int(model.site_bodyid[site])
    rng = np.random.default_rng(30)
    dh, force, tau = ffi.new("double[3]"), ffi.new("double[3]"), ffi.new("double[3]")
    for _ in range(50):
        q = rng.uniform([-2.5, -2.0, 0.2], [2.5, 0.1, 2.2])
        f = rng.uniform(-10.0, 10.0, 3)
        data.qpos[:3] = q
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        expected = np.zeros(model.nv)
        mujoco.mj_applyFT(model, data, f, np.zeros(3), data.site_xpos[site].copy(), body, expected)
        dh[0:3], force[0:3] = list(q), list(f)
        lib.crs_push_joint_torques(dh, force, tau)
        assert np.allclose(list(tau), expected[:3], rtol=1e-9, atol=1e-12)
        # and the site is where the course's forward kinematics puts the end effector
        assert np.allclose(data.site_xpos[site], crs.fk_dh(q) * 0.0254, atol=1e-12)


# -- runs: Lab 4 under lab4_push ----------------------------------------------------------------

@pytest.fixture(scope="module")
def world_x_weak():
    return simulate(LAB, "lab4_push", log=True)


@pytest.fixture(scope="module")
def rotated_y_weak():
    g = lab_gains()
    # the handout's first rotated case: thz = pi/3 with N's y weak (the lab's x and y gains swapped)
    return simulate(LAB, with_sets("lab4_push", {"thz": math.pi / 3, "KPx": g["KPy"], "KDx": g["KDy"],
                                                 "KPy": g["KPx"], "KDy": g["KDx"]}), log=True)


def test_a_lab_weak_along_world_x_gives_way_along_x_by_f_over_kp(world_x_weak):
    run, g = world_x_weak, lab_gains()
    assert run.status.value == "ok"
    assert g["thz"] == g["thx"] == g["thy"] == 0.0 and g["KPx"] < g["KPy"] == g["KPz"]
    moved = half_swing(run)
    assert abs(moved[0]) >= 5 * abs(moved[1]) and abs(moved[0]) >= 5 * abs(moved[2]), moved
    expected = PUSH_N / np.array([g["KPx"], g["KPy"], g["KPz"]])
    assert moved[0] == pytest.approx(expected[0], rel=0.2)


def test_a_lab_weak_along_its_rotated_frames_y_gives_way_along_that_axis(rotated_y_weak):
    run, g = rotated_y_weak, lab_gains()
    assert run.status.value == "ok"
    r = lab4_frame_matrix(math.pi / 3, 0.0, 0.0)
    moved_n = r.T @ half_swing(run)          # along N's x, y, z
    assert abs(moved_n[1]) >= 5 * abs(moved_n[0]) and abs(moved_n[1]) >= 5 * abs(moved_n[2]), moved_n
    along_y = r[:, 1] @ PUSH_N               # the push's component along N's y: 5 (cos 60 - sin 60) N
    assert along_y == pytest.approx(5 * (0.5 - S3 / 2))
    assert moved_n[1] == pytest.approx(along_y / g["KPx"], rel=0.2)   # N's y has the lab's weak gain


def test_a_push_given_in_the_rotated_frame_moves_the_lab_along_that_axis(tmp_path):
    g = lab_gains()
    text = load_scenario("lab4_push").source
    scenario = Path(text).read_text().replace('force_n = [5, 5, 5]\nperiod = 2.0',
                                              'force_n = [0, 5, 0]\nframe_deg = {thz = 60}\nperiod = 2.0')
    assert "frame_deg" in scenario
    (tmp_path / "push_in_n.toml").write_text(scenario.replace("end = 16.0", "end = 10.0"))
    sc = with_sets(str(tmp_path / "push_in_n.toml"), {"thz": math.pi / 3, "KPx": g["KPy"], "KDx": g["KDy"],
                                                      "KPy": g["KPx"], "KDy": g["KDx"]})
    run = simulate(LAB, sc, log=True)
    r = lab4_frame_matrix(math.pi / 3, 0.0, 0.0)
    tick = run.log["tick"][:, 0]
    first = run.log["push_force"][np.searchsorted(tick, FIRST_PUSH_TICK)]
    assert np.allclose(first, [-5 * S3 / 2, 2.5, 0.0], atol=1e-12)       # R F, along N's y
    moved_n = r.T @ half_swing(run, periods=2)
    assert moved_n[1] == pytest.approx(5.0 / g["KPx"], rel=0.2)
    assert abs(moved_n[1]) >= 5 * abs(moved_n[0]) and abs(moved_n[1]) >= 5 * abs(moved_n[2]), moved_n


def test_the_logs_push_is_the_square_wave_and_its_ee_the_courses_fk(world_x_weak):
    log = world_x_weak.log
    tick = log["tick"][:, 0]
    assert tick[0] == 0 and np.array_equal(tick, np.arange(len(tick)))
    since = tick - FIRST_PUSH_TICK
    sign = np.where(since < 0, 0.0, np.where((since // HALF_PERIOD_TICKS) % 2 == 0, 1.0, -1.0))
    assert np.array_equal(log["push_force"], sign[:, None] * PUSH_N)
    assert np.allclose(log["ee"], crs.fk_dh(log["qpos_dh_rad"]) * 0.0254, atol=1e-12)


def test_the_transcript_and_the_log_are_the_same_at_fast_and_in_other_chunks():
    # 5 s of pushes; at x13.7 chunks are 274 ticks, so the sign flips in the middle of chunks
    fast = simulate(LAB, "lab4_push", log=True, duration_s=11.0)
    chunked = simulate(LAB, "lab4_push", log=True, duration_s=11.0, speed=13.7)
    assert fast.transcript == chunked.transcript and fast.transcript.count(b"\n") == 14  # every 0.5 s
    for column in ("ee", "push_force", "enc_rad", "tau_applied"):
        assert np.array_equal(fast.log[column], chunked.log[column]), column
