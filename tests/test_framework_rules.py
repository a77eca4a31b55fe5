"""One test per rule of the real framework's 1 ms tick (docs/framework.md sections 3 to 6), each asserting
the rule's own number.

Every number is written here by hand from the course's facts, and where crslab exposes it (the C
headers through ``crslab.framework_facts`` and ``crslab.crs``) the exposed value is checked
against the hand-written one, so that a changed header is caught even where behaviour would hide
it. The rules are checked on a few ticks, never on long runs: the emulated board's functions are
called directly through cffi on a lab's shared object (the hold controller, the hand, the encoders,
the motor board), and the framework's tick through the worker in this process (the envelope's
flag, the clamp, the startup gate, ``error``'s delay, the print triggers, the wrist e-stop), with
the arm put at each pose by hand before each tick.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from cffi import FFI

from crslab import crs, framework_facts, resources
from crslab.cheaders import cdef_from_header
from crslab.run.api import make_config
from crslab.run.inprocess import InProcessRun
from crslab.scenario.fault_events import WristEstop
from crslab.scenario.load import load_scenario
from crslab.worker.board_ffi import BOARD_HEADERS, native_board_ffi

LAB = Path(__file__).parent / "labs" / "framework_rules.c"
LAB_GEN_B = Path(__file__).parent / "labs" / "framework_rules_gen_b.c"
HALF_PI = math.pi / 2
RAD_PER_COUNT = math.pi / 144000  # 288 000 counts per motor revolution
F32 = np.float32

# the course's numbers, by hand
ENVELOPE_TH1_RAD = 0.6667 * math.pi
ENVELOPE_TH2_RAD = (-2.3, 0.15)
ENVELOPE_TH3_RAD = (0.15, 2.3)
ENVELOPE_Z_MIN_IN = 4.0
CLAMP_UNITS = 5.0
STARTUP_TICKS = 4100
KP_FAR, KP_NEAR, KP_SWITCH_RAD, KD = 15.0, 25.0, 0.1, 1.0
REANCHOR_RAD = 0.15
WRIST_ESTOP_RAD = 0.11
MB_COUNTS_PER_UNIT, MB_REJECT_COUNTS, MB_LIMIT_COUNTS = 300, 1500, 1200
MB_OVER_LIMIT_MS, MB_TIMEOUT_MS = 500, 100

BOARD_FUNCTIONS = """
void crs_motor_board_init(crs_motor_board *mb);
int crs_motor_board_step(int32_t model, crs_motor_board *mb, int64_t tick, const double *command_units);
extern long rule_calls;
extern int rule_post;
"""
LAB_VARIABLES = {LAB: "extern float rule_tau[3];\nextern int rule_error;\n",
                 LAB_GEN_B: "extern int UARTprint;\n"}


class Board:
    """The test lab's worker in this process, and the board's own functions in its shared object."""

    def __init__(self, scenario: str = "hands_off", startup_delay: bool = False, lab: Path = LAB) -> None:
        # native: the board's own functions are reached in the lab's shared object (the WebAssembly
        # firmware runs on the same board: tests/test_wasm_firmware.py compares the two)
        self.run = InProcessRun(make_config(lab, scenario, startup_delay=startup_delay, sandbox=False,
                                            native=True))
        self.worker = self.run.worker
        self.sim = self.worker.sim
        self.ffi = FFI()
        for header in (*BOARD_HEADERS, "board/debug.h", "board/framework.h"):
            self.ffi.cdef(cdef_from_header(resources.path("csrc", *header.split("/")).read_text()))
        self.ffi.cdef(BOARD_FUNCTIONS + LAB_VARIABLES[lab])
        # the library the worker loaded (found among those loaded, not opened again)
        self.lib = self.ffi.dlopen(str(self.worker.config.build.shared_object))

    def new_sim(self) -> object:
        """A fresh board (``crs_board_defaults``) that sees the worker's firmware (its variables)."""
        sim = self.ffi.new("crs_board *")
        self.lib.crs_board_defaults(sim)
        worker_ffi = native_board_ffi()  # the worker's board's declarations
        worker_fw = int(worker_ffi.cast("uintptr_t", worker_ffi.addressof(self.sim, "fw")))
        self.ffi.memmove(self.ffi.addressof(sim, "fw"), self.ffi.cast("void *", worker_fw),
                         self.ffi.sizeof("crs_fw_view"))
        return sim

    def tick(self, dh_rad: object | None = None) -> None:
        """Run one tick, with the arm put at ``dh_rad`` (still) first when given."""
        if dh_rad is not None:
            self.worker.data.qpos[:3] = dh_rad
            self.worker.data.qvel[:3] = 0.0
        self.worker.run(int(self.sim.tick) + 1)

    def applied(self) -> list[float]:
        return [float(self.sim.applied[j]) for j in range(3)]

    def hold_out(self) -> list[float]:
        return [float(self.sim.hold.out[j]) for j in range(3)]

    def set_tau(self, tau: tuple[float, float, float]) -> None:
        for j in range(3):
            self.lib.rule_tau[j] = tau[j]


@pytest.fixture
def board() -> Board:
    return Board()


def motor_of(dh: tuple[float, float, float]) -> np.ndarray:
    """Motor angles of DH angles, by the course's formulas (th2 = m2 - pi/2, th3 = m3 - m2 + pi/2)."""
    th1, th2, th3 = dh
    return np.array([th1, th2 + HALF_PI, th3 + th2])


def z_in(motor: np.ndarray) -> float:
    """The framework's end-effector height: 10 (1 + cos m2 - sin m3) inches."""
    return 10.0 * (1.0 + math.cos(motor[1]) - math.sin(motor[2]))


# -- the numbers the headers hold ----------------------------------------------------------------

def test_the_headers_hold_the_courses_numbers():
    assert crs.ENVELOPE_TH1_MAX_RAD == pytest.approx(ENVELOPE_TH1_RAD, abs=1e-12)
    assert crs.ENVELOPE_TH2_RAD == ENVELOPE_TH2_RAD and crs.ENVELOPE_TH3_RAD == ENVELOPE_TH3_RAD
    assert crs.ENVELOPE_Z_MIN_IN == ENVELOPE_Z_MIN_IN
    ff = framework_facts
    assert (ff.CLAMP_UNITS, ff.STARTUP_TICKS) == (CLAMP_UNITS, STARTUP_TICKS)
    hold = (ff.HOLD_KP_FAR, ff.HOLD_KP_NEAR, ff.HOLD_KP_SWITCH_RAD, ff.HOLD_KD)
    assert hold == (KP_FAR, KP_NEAR, KP_SWITCH_RAD, KD)
    assert ff.HOLD_REANCHOR_RAD == REANCHOR_RAD and ff.WRIST_ESTOP_RAD == WRIST_ESTOP_RAD
    assert ff.ENCODER_COUNTS_PER_REV == 288000
    assert ff.MB_COUNTS_PER_UNIT == MB_COUNTS_PER_UNIT and ff.MB_LIMIT_UNITS == 4.0
    assert (ff.MB_OVER_LIMIT_MS, ff.MB_TIMEOUT_MS) == (MB_OVER_LIMIT_MS, MB_TIMEOUT_MS)


# -- the safety envelope: every bound from both sides --------------------------------------------

DELTA_RAD = 0.002  # about 92 counts: far beyond the encoders' quantization
CENTRE_DH = (0.3, -1.08, 1.22)  # every other bound at least 1 rad away, z = 15.4 in
EDGES = [
    # name, DH pose on the bound, the DH coordinate the bound is on, the outward direction
    ("th1 <= +0.6667 pi", (ENVELOPE_TH1_RAD, -1.08, 1.22), 0, +1),
    ("th1 >= -0.6667 pi", (-ENVELOPE_TH1_RAD, -1.08, 1.22), 0, -1),
    ("th2 >= -2.3", (0.3, -2.3, 1.22), 1, -1),
    ("th2 <= 0.15", (0.3, 0.15, 0.30), 1, +1),  # th3 and z leave room: 0.15 rad and 0.9 in
    ("th3 >= 0.15", (0.3, -1.08, 0.15), 2, -1),
    ("th3 <= 2.3", (0.3, -1.08, 2.3), 2, +1),
]


def edge_poses(edge: tuple[str, tuple[float, float, float], int, int]) -> tuple[np.ndarray, np.ndarray]:
    """DH poses DELTA_RAD inside and outside one bound."""
    _, on, coord, outward = edge
    inside, outside = np.array(on), np.array(on)
    inside[coord] -= outward * DELTA_RAD
    outside[coord] += outward * DELTA_RAD
    return inside, outside


def z_poses() -> tuple[np.ndarray, np.ndarray]:
    """DH poses 0.01 in above and below z = 4 in (th1 0.3, th2 -0.36; th3 solved from the height)."""
    m2 = -0.36 + HALF_PI
    out = []
    for z in (ENVELOPE_Z_MIN_IN + 0.01, ENVELOPE_Z_MIN_IN - 0.01):
        m3 = math.asin(1.0 + math.cos(m2) - z / 10.0)
        out.append(crs.motor_to_dh(np.array([0.3, m2, m3])))
    return out[0], out[1]


def all_edges() -> list[tuple[str, np.ndarray, np.ndarray]]:
    return [(e[0], *edge_poses(e)) for e in EDGES] + [("z >= 4 in", *z_poses())]


@pytest.mark.parametrize("name,inside,outside", all_edges(), ids=[e[0] for e in all_edges()])
def test_each_envelope_bound_from_both_sides(name, inside, outside):
    m_in, m_out = motor_of(tuple(inside)), motor_of(tuple(outside))
    np.testing.assert_allclose(crs.dh_to_motor(inside), m_in, atol=1e-12)
    if name.startswith("z"):
        assert z_in(m_in) == pytest.approx(4.01) and z_in(m_out) == pytest.approx(3.99)
    assert not crs.outside_envelope(m_in) and crs.outside_envelope(m_out)
    assert not crs.outside_envelope(motor_of(CENTRE_DH))


def test_at_each_bound_inside_uses_the_labs_torque_and_outside_the_hold_with_error_one_tick_late(board):
    lab = board.lib
    for name, inside, outside in all_edges():
        board.tick(CENTRE_DH)
        board.tick(inside)
        assert board.sim.safety_flag == 0 and lab.rule_error == 0, name
        assert board.applied() == [0.75, -0.5, 0.25], name  # the lab's torques
        # inside, the references follow the arm
        assert [board.sim.hold.ref_rad[j] for j in range(3)] == [F32(board.sim.enc_rad[j]) for j in range(3)]
        ref_inside = [board.sim.hold.ref_rad[j] for j in range(3)]
        board.tick(outside)
        assert board.sim.safety_flag == 1, name
        assert lab.rule_error == 0, name  # this tick's lab() was handed the last tick's flag
        hold = np.clip(board.hold_out(), -CLAMP_UNITS, CLAMP_UNITS)
        assert board.applied() == hold.tolist() and board.applied() != [0.75, -0.5, 0.25], name
        # outside, a reference within 0.15 rad of its angle stays where the arm left the envelope
        assert [board.sim.hold.ref_rad[j] for j in range(3)] == ref_inside, name
        board.tick(outside)
        assert lab.rule_error == 1, name
        board.tick(inside)
        assert lab.rule_error == 1 and board.sim.safety_flag == 0, name  # back in: told next tick
        assert board.applied() == [0.75, -0.5, 0.25], name
        board.tick(inside)
        assert lab.rule_error == 0, name


# -- the clamp -----------------------------------------------------------------------------------

def test_every_command_is_clamped_to_plus_minus_5_units_on_both_sides(board):
    board.tick(CENTRE_DH)
    for tau, want in [((7.0, -7.0, 4.99), (5.0, -5.0, float(F32(4.99)))),
                      ((-5.25, 5.25, -4.99), (-5.0, 5.0, float(F32(-4.99)))),
                      ((40.0, -100.0, 5.0), (5.0, -5.0, 5.0))]:
        board.set_tau(tau)
        board.tick(CENTRE_DH)
        assert board.applied() == list(want)
    # the hold controller's output is clamped too: the arm put from the centre to just past th1's
    # bound (1.8 rad in one ms, on either side) makes it far beyond 5 units
    centre = np.array(CENTRE_DH)
    edge_out = np.array(EDGES[0][1]) + [DELTA_RAD, 0, 0]
    board.tick(centre)
    board.tick(edge_out)
    assert board.sim.safety_flag == 1 and abs(board.hold_out()[0]) > CLAMP_UNITS
    assert board.applied()[0] == -CLAMP_UNITS  # pulled back, toward the envelope
    board.tick(centre)
    board.tick(-edge_out * [1, 0, 0] + centre * [0, 1, 1])
    assert board.sim.safety_flag == 1 and board.applied()[0] == CLAMP_UNITS


# -- the hold controller ---------------------------------------------------------------------------

def test_the_hold_references_start_at_0_so_tick_0_pulls_toward_motor_zero():
    board = Board(startup_delay=True)
    assert [board.sim.hold.ref_rad[j] for j in range(3)] == [0.0, 0.0, 0.0]
    board.tick()
    enc = np.array([board.sim.enc_rad[j] for j in range(3)], F32)
    np.testing.assert_allclose(enc, [0.0, -0.42, 0.24], atol=RAD_PER_COUNT)
    # e = 0 - angle, beyond 0.1 rad: Kp 15; v = (angle - 0) / 1 ms averaged with two zeros
    want = KP_FAR * -enc - (enc / F32(0.001)) / 3
    np.testing.assert_allclose(board.hold_out(), want, rtol=1e-6)
    np.testing.assert_allclose(board.hold_out(), [0.0, 146.3, -83.6], atol=1e-3)
    assert [board.sim.hold.ref_rad[j] for j in range(3)] == [0.0, 0.0, 0.0]  # not before the gate


def hold_at_rest(board: Board, ref: list[float], angle: list[float]):
    """A hold controller whose arm has rested at ``angle`` (no velocity) with references ``ref``."""
    h = board.ffi.new("crs_hold *")
    for j in range(3):
        h.ref_rad[j] = ref[j]
        h.prev_enc_rad[j] = angle[j]
    return h


def test_the_hold_gain_is_25_within_0_1_rad_of_error_and_15_beyond(board):
    angle = [0.5, -1.0, 1.5]
    for e, kp in [(0.0999, KP_NEAR), (-0.0999, KP_NEAR), (0.1001, KP_FAR), (-0.1001, KP_FAR), (0.05, KP_NEAR),
                  (0.14, KP_FAR)]:
        ref = [float(F32(a + e)) for a in angle]
        h = hold_at_rest(board, ref, angle)
        board.lib.crs_hold_update(h, angle)
        want = kp * (F32(ref[0]) - F32(angle[0]))
        np.testing.assert_allclose(list(h.out), [want] * 3, rtol=1e-5, atol=0, err_msg=f"e = {e}")


def test_the_hold_damping_is_kd_1_on_a_velocity_averaged_recursively_over_3_ticks(board):
    # the arm turns 0.001 rad per ms (1 rad/s) away from the reference it rested at: e = -k step,
    # Kp 25; joint 1 averages v with the two previous averages (r/3, 4r/9, 16r/27, 55r/81), joint 2
    # (the real board's quirk) with the older one twice (r/3, r/3, 5r/9, 5r/9); joint 3 as joint 1
    start = [0.5, -1.0, 1.5]
    h = hold_at_rest(board, start, start)
    step, r = 0.001, 1.0
    v1 = [r / 3, 4 * r / 9, 16 * r / 27, 55 * r / 81]
    v2 = [r / 3, r / 3, 5 * r / 9, 5 * r / 9]
    for k in range(4):
        angle = [a + (k + 1) * step for a in start]
        board.lib.crs_hold_update(h, angle)
        e = -(k + 1) * step
        np.testing.assert_allclose(list(h.out), [KP_NEAR * e - KD * v1[k], KP_NEAR * e - KD * v2[k],
                                                 KP_NEAR * e - KD * v1[k]], atol=2e-4, err_msg=f"tick {k}")


def test_outside_a_reference_reanchors_only_beyond_0_15_rad_and_inside_it_follows(board):
    angle = [0.5, -1.0, 1.5]
    for gap, moves in [(0.1499, False), (-0.1499, False), (0.1501, True), (-0.1501, True)]:
        ref = [float(F32(a + gap)) for a in angle]
        h = hold_at_rest(board, ref, angle)
        board.lib.crs_hold_reanchor(h, angle)
        want = [F32(a) for a in angle] if moves else [F32(x) for x in ref]
        assert list(h.ref_rad) == want, gap
    h = hold_at_rest(board, [0.0, 0.0, 0.0], angle)
    board.lib.crs_hold_follow(h, angle)
    assert list(h.ref_rad) == [F32(a) for a in angle]


# -- the startup gate ---------------------------------------------------------------------------

def test_the_first_lab_call_is_at_tick_4100_and_nothing_reaches_the_motors_before():
    board = Board(startup_delay=True)
    board.set_tau((0.75, -0.5, 0.25))
    gate = board.worker
    gate.run(STARTUP_TICKS)
    assert board.lib.rule_calls == 0 and board.sim.lab_calls == 0
    assert board.applied() == [0.0, 0.0, 0.0] and abs(board.hold_out()[1]) > 0.01  # the hold runs, unused
    assert list(board.sim.hold.ref_rad) == [0.0, 0.0, 0.0]
    board.tick()  # tick 4100
    assert board.lib.rule_calls == 1 and board.sim.tick == STARTUP_TICKS + 1
    assert board.applied() == [0.75, -0.5, 0.25]


# -- the print triggers ---------------------------------------------------------------------------

def test_gen_a_prints_from_lab_at_once_and_runs_printing_once_after_lab_per_tick_posted(board):
    board.tick(CENTRE_DH)
    board.tick(CENTRE_DH)
    assert board.run.run(int(board.sim.tick) + 5) == b""  # nothing asked, nothing printed
    board.lib.rule_post = 1
    sent = board.run.run(int(board.sim.tick) + 1)
    # the lab's own line, then printing() once (two posts in one tick), after lab() returned
    assert sent == b"lab 8\n\rprinting 8\n\r" and board.sim.printing_runs == 1
    assert board.run.run(int(board.sim.tick) + 5) == b"" and board.sim.printing_runs == 1


def test_gen_b_runs_printing_once_after_lab_when_uartprint_is_1_and_clears_it():
    board = Board(lab=LAB_GEN_B)
    assert board.run.run(5) == b""
    board.lib.rule_post = 1
    # the lab's own line, then printing() with UARTprint already cleared, once
    assert board.run.run(6) == b"lab 6\n\rprinting 6 UARTprint 0\n\r"
    assert board.lib.UARTprint == 0 and board.sim.printing_runs == 1
    assert board.run.run(20) == b"" and board.sim.printing_runs == 1


# -- the wrist e-stop ------------------------------------------------------------------------------

def test_a_wrist_turned_past_0_11_rad_latches_every_output_to_zero(tmp_path):
    assert not WristEstop(tick=0, wrist_rad=0.11).latches and not WristEstop(tick=0, wrist_rad=-0.11).latches
    assert WristEstop(tick=0, wrist_rad=0.1101).latches and WristEstop(tick=0, wrist_rad=-0.1101).latches
    scenario = tmp_path / "wrist.toml"
    scenario.write_text('end = 1\n[[event]]\nat = 0.003\nkind = "estop"\nwrist_rad = 0.11\n'
                        '[[event]]\nat = 0.006\nkind = "estop"\nwrist_rad = -0.1101\n')
    board = Board(str(scenario))
    for _ in range(6):  # ticks 0-5: 0.11 rad at tick 3 is not past the e-stop's threshold
        board.tick(CENTRE_DH)
        assert board.applied() == [0.75, -0.5, 0.25]
    for _ in range(3):  # ticks 6-8: -0.1101 rad at tick 6 is
        board.tick(CENTRE_DH)
        assert board.applied() == [0.0, 0.0, 0.0] and board.sim.estop_latched == 1
    assert board.lib.rule_calls == 9  # lab() still runs


# -- the encoders -------------------------------------------------------------------------------

def test_encoders_are_whole_counts_plus_the_offset_rounded_to_float32(board):
    sim = board.new_sim()
    rest = (0.0, -0.42, 0.24)
    for j in range(3):
        sim.config.rest_motor_rad[j] = rest[j]
    # 5659.7 counts on joint 1, -1234.6 on joint 2, 11936.5 + a little on joint 3: rounded to the
    # nearest count (5660, -1235, 11937), not truncated
    counts_want = (5660, -1235, 11937)
    motor = [5659.7 * RAD_PER_COUNT, -0.42 - 1234.6 * RAD_PER_COUNT, 0.24 + 11936.51 * RAD_PER_COUNT]
    enc = board.ffi.new("double[3]")
    board.lib.crs_read_encoders(sim, motor, enc)
    offsets = (0.0, float(F32(-0.42)), float(F32(0.24)))  # the lab's float offsets
    for j in range(3):
        exact = counts_want[j] * RAD_PER_COUNT + offsets[j]
        assert enc[j] == float(F32(exact)), j
        if j > 0:
            assert enc[j] != exact  # the rounding to float is there to see
    assert enc[0] == float(F32(5660 * RAD_PER_COUNT))  # joint 1: whole counts, no offset


# -- the scenario's hand -------------------------------------------------------------------------

def test_the_hand_moves_along_a_minimum_jerk_path_for_the_scenarios_duration(board, tmp_path):
    scenario = tmp_path / "hand.toml"
    scenario.write_text('end = 2\n[[event]]\nat = 0.5\nkind = "hand"\ndh_deg = [20, -40, 60]\n'
                        'duration = 0.4\n')
    (move,) = load_scenario(str(scenario)).events
    assert (move.tick, move.duration_ticks) == (500, 400)
    hand, gains = board.ffi.new("crs_hand *"), board.ffi.new("crs_hand_config *")
    q, qd = board.ffi.new("double[3]"), board.ffi.new("double[3]")
    h = hand[0]
    h.active, h.start_tick, h.duration_ticks = 1, 500, 400
    target = np.radians([20.0, -40.0, 60.0])
    for j in range(3):
        h.target_dh_rad[j] = target[j]
    gains.max_nm = 1e9

    path = board.ffi.new("crs_hand_path *")
    board.lib.crs_hand_plan(hand, path)  # as the tick loop does per chunk

    def force(tick: int, kp: float, kd: float) -> np.ndarray:
        gains.kp_nm_per_rad, gains.kd_nm_s_per_rad = kp, kd
        board.lib.crs_hand_step_along(gains, hand, path, tick, q, qd)
        return np.array(list(h.force_nm))

    # with the arm at 0, a force of kp * error is the path itself: L (10 s^3 - 15 s^4 + 6 s^5)
    for tick, share in [(500, 0.0), (600, 0.103515625), (700, 0.5), (800, 0.896484375), (900, 1.0),
                        (1200, 1.0)]:
        np.testing.assert_allclose(force(tick, 1.0, 0.0), share * target, atol=1e-12, err_msg=str(tick))
    # and kd * error its speed, which peaks at 1.875 L / T halfway
    np.testing.assert_allclose(force(700, 0.0, 1.0), 1.875 * target / 0.4, rtol=1e-12)
    np.testing.assert_allclose(force(900, 0.0, 1.0), 0.0, atol=1e-12)


# -- the motor board ----------------------------------------------------------------------------

PICCOLO = framework_facts.MOTOR_BOARDS["piccolo"]


def motor_board(board: Board):
    mb = board.ffi.new("crs_motor_board *")
    board.lib.crs_motor_board_init(mb)
    return mb


def test_the_motor_board_rejects_a_command_beyond_1500_counts_on_either_side(board):
    for sign in (1, -1):
        mb = motor_board(board)
        board.lib.crs_motor_board_step(PICCOLO, mb, 0, [sign * 2.0, 0.0, 0.0])
        board.lib.crs_motor_board_step(PICCOLO, mb, 1, [sign * 5.0, 0.0, 0.0])  # 1500 counts: taken
        assert mb.out_units[0] == sign * 5.0
        board.lib.crs_motor_board_step(PICCOLO, mb, 2, [sign * 5.004, 0.0, 0.0])  # 1501.2: rejected
        assert mb.out_units[0] == sign * 5.0 and mb.since_command == 1  # as if nothing arrived


def test_the_motor_board_cuts_out_after_500_ms_beyond_1200_counts_on_either_side(board):
    for sign in (1, -1):
        mb = motor_board(board)
        for t in range(2000):  # 1200 counts is within the limit
            board.lib.crs_motor_board_step(PICCOLO, mb, t, [sign * 4.0, 0.0, 0.0])
        assert mb.off == 0 and mb.out_units[0] == sign * 4.0
        over = [0.0, sign * 4.004, 0.0]  # 1201.2 counts on joint 2
        for t in range(MB_OVER_LIMIT_MS):
            board.lib.crs_motor_board_step(PICCOLO, mb, 2000 + t, over)
        assert mb.off == 0 and mb.out_units[1] == sign * 1201 / 300
        board.lib.crs_motor_board_step(PICCOLO, mb, 2500, over)  # the 501st over the limit
        assert mb.off == 1 and list(mb.out_units) == [0.0, 0.0, 0.0]
        assert (mb.event_tick[0], mb.event_joint[0], mb.event_off[0]) == (2500, 2, 1)
        board.lib.crs_motor_board_step(PICCOLO, mb, 2501, [0.0, sign * 4.0, 0.0])  # within: back on at once
        assert mb.off == 0 and mb.over_ticks[1] == 0


def test_the_motor_board_cuts_out_after_100_ms_without_a_command(board):
    mb = motor_board(board)
    board.lib.crs_motor_board_step(PICCOLO, mb, 0, [1.0, -1.0, 0.5])
    for t in range(1, MB_TIMEOUT_MS):
        board.lib.crs_motor_board_step(PICCOLO, mb, t, board.ffi.NULL)
    assert mb.off == 0 and list(mb.out_units) == [1.0, -1.0, 0.5]  # 99 ms: the outputs hold
    board.lib.crs_motor_board_step(PICCOLO, mb, MB_TIMEOUT_MS, board.ffi.NULL)
    assert mb.off == 1 and list(mb.out_units) == [0.0, 0.0, 0.0]
    assert (mb.event_tick[0], mb.event_joint[0]) == (MB_TIMEOUT_MS, 0)
