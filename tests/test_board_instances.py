"""Board instances (crslab/run/board_client.py, crslab/worker/main.py, csrc/board/firmware_wasm.c):
many labs in one worker process share one wasmtime engine and one compiled module per distinct
firmware, each in a store of its own with its own deadline; a hostile lab among 20 ends its own run
and no other's, and every well-behaved lab prints what it prints alone. The board takes a run's
settings in one call (crs_board_configure) and a scenario's event in another
(crs_board_apply_event): what it holds is what was asked, worked out here independently."""

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from crslab._bindings import constants
from crslab.plant.plant_params import PlantParams
from crslab.run.api import simulate
from crslab.run.assemble import make_config
from crslab.run.board_client import BoardClient, InstanceNotOpened
from crslab.run.diagnosis import Ending
from crslab.worker.board_settings import board_settings, event_struct

ROOT = Path(__file__).resolve().parents[1]
LABS = ROOT / "tests" / "labs"
STOPS = {"does_not_compile.c", "crash_after_5s.c", "hang_after_5s.c", "busy_wait_global_gen_b.c",
         "implicit_decls_gen_b.c"}  # the last two stop on the board's build (a busy-wait, a lost pointer)
WELL_BEHAVED = sorted(p for p in [*(ROOT / "csrc" / "labs").glob("*.c"), *LABS.glob("*.c")]
                      if p.name not in STOPS)[:17]
END_TICK = 5000
CHUNK_TICKS = 250

HOSTILE = {
    # a NULL write at the lab's line (the check compiled into the lab stops it)
    "null_write.c": "    if (mycount == 200) *nowhere = theta1motor;\n",
    # a busy-wait nothing ends: interrupted at its own deadline
    "spins.c": "    if (mycount == 300) { while (!ready) { spun++; } }\n",
    # a line longer than the board's format buffer (2048 characters)
    "long_line.c": '    if (mycount == 400) serial_printf(&SerialA, "%3000d\\n\\r", 1);\n',
}
HOSTILE_TEXT = """/* Test lab: counts its calls and prints the count every 100 ms; then, once, {what}. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
volatile int ready = 0;
volatile long spun = 0;
float *nowhere; /* a pointer nobody set */

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
{act}    if ((mycount % 100) == 0) SWI_post(&SWI_printf);
    mycount++;
}}

void printing(void)
{{
    serial_printf(&SerialA, "count %ld\\n\\r", mycount);
}}
"""
HANG_DEADLINE_S = 0.3


@pytest.fixture(scope="module")
def hostile_labs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hostile")
    labs = {}
    for name, act in HOSTILE.items():
        path = folder / name
        path.write_text(HOSTILE_TEXT.format(what=name.removesuffix(".c").replace("_", " "), act=act))
        labs[name] = path
    return labs


@pytest.fixture(scope="module")
def twenty_in_one_worker(hostile_labs):
    """The 17 well-behaved labs and the 3 hostile ones, each an instance of one worker, run together
    to END_TICK in chunks (one request per chunk for all of them): each one's serial bytes, how each
    run that stopped early ended (its code and trap, or why it never ran), and whether the worker
    was still alive at the end."""
    configs = {lab: make_config(lab, "tour") for lab in [*WELL_BEHAVED, *hostile_labs.values()]}
    worker = BoardClient()
    printed: dict[Path, bytearray] = {lab: bytearray() for lab in configs}
    ended: dict[Path, tuple] = {}
    try:
        handles = {}
        for lab, config in configs.items():
            deadline_s = HANG_DEADLINE_S if lab.name == "spins.c" else 2.0
            try:
                handles[lab] = worker.open(config, deadline_s=deadline_s)
            except InstanceNotOpened as exc:
                ended[lab] = ("not opened", str(exc.reply))
        tick = 0
        while tick < END_TICK:
            tick = min(END_TICK, tick + CHUNK_TICKS)
            running = [(lab, h) for lab, h in handles.items() if lab not in ended]
            for (lab, h), ran in zip(running, worker.run([(h, tick) for _, h in running]), strict=True):
                h.block.drain(lambda t, c: None, lambda t, data, out=printed[lab]: out.extend(data))
                if isinstance(ran, Ending):
                    ended[lab] = ("the worker ended", ran.message)
                elif ran.code not in (0, constants.CRS_RUN_SERIAL_FULL):
                    ended[lab] = (ran.code, ran.trap)
            for lab, h in handles.items():  # the worker itself ended: every instance of it did
                if h.ending is not None and lab not in ended:
                    ended[lab] = ("the worker ended", h.ending.message)
        for lab, h in handles.items():
            printed[lab] += h.block.take_line()
        alive = worker.alive
        for h in handles.values():
            worker.release(h)
    finally:
        worker.close()
    return printed, ended, alive


def test_a_hostile_lab_among_twenty_ends_only_its_own_run(twenty_in_one_worker, hostile_labs):
    printed, ended, alive = twenty_in_one_worker
    assert alive
    c = constants
    by_name = {lab.name: result for lab, result in ended.items()}
    assert set(by_name) == set(HOSTILE), by_name  # the three hostile labs, and no other
    code, trap = by_name["null_write.c"]
    assert code == c.CRS_RUN_TRAPPED and trap["kind"] == c.CRS_FW_TRAP_NULL and trap["tick"] == 4100 + 200
    code, trap = by_name["spins.c"]
    assert code == c.CRS_RUN_TRAPPED and trap["kind"] == c.CRS_FW_TRAP_INTERRUPT
    assert trap["tick"] == 4100 + 300
    code, trap = by_name["long_line.c"]
    assert code == c.CRS_RUN_PRINTF_OVERFLOW and trap is None
    # what it printed before it stopped (printing() runs after lab() counted the call): each line whole
    assert bytes(printed[hostile_labs["spins.c"]]) == b"count 1\n\rcount 101\n\rcount 201\n\r"


@pytest.mark.parametrize("lab", WELL_BEHAVED, ids=lambda p: p.name)
def test_each_neighbour_prints_what_it_prints_alone(twenty_in_one_worker, lab):
    printed, ended, _ = twenty_in_one_worker
    assert lab not in ended
    alone = simulate(lab, "tour", duration_s=END_TICK / 1000)
    assert alone.status == "ok", alone.message
    assert bytes(printed[lab]) == alone.transcript


SHARING = """
import json, sys
from crslab._core import lib  # (the test of the C core itself may reach past crslab._bindings)
from crslab.scenario.load import load_scenario
from crslab.run.assemble import make_config
from crslab.run.shared_block import SharedBlock
from crslab.worker import worker_messages
from crslab.worker.main import BoardInstances

a, b = sys.argv[1], sys.argv[2]
configs = [make_config(a, "tour"), make_config(a, "tour"), make_config(b, "tour"),
           make_config(a, "end_mass")]
worker = BoardInstances()
blocks = [SharedBlock.new() for _ in configs]
for i, (config, block) in enumerate(zip(configs, blocks)):
    assert isinstance(worker.open(i, config, block.memory, 2.0, []), worker_messages.Ready)
boards = worker.instances
seen = {"modules": lib.crs_fw_wasm_module_count(), "refs": [boards[i].module_refs for i in range(4)],
        "same_model_01": boards[0].model is boards[1].model,
        "same_model_02": boards[0].model is boards[2].model,
        "same_model_03": boards[0].model is boards[3].model}
worker.answer(worker_messages.Stop(0))
seen["after_stop_0"] = [lib.crs_fw_wasm_module_count(), boards[1].module_refs]
worker.answer(worker_messages.Stop(2))
seen["after_stop_2"] = lib.crs_fw_wasm_module_count()
worker.close()
seen["after_close"] = lib.crs_fw_wasm_module_count()
print(json.dumps(seen))
"""
"""Run in a process of its own: wasmtime's signal handlers stay out of the test process."""


def test_instances_of_one_lab_share_one_compiled_module_and_other_labs_get_their_own():
    a, b = ROOT / "csrc" / "labs" / "lab1_kinematics.c", ROOT / "csrc" / "labs" / "lab2_square_pid.c"
    r = subprocess.run([sys.executable, "-c", SHARING, str(a), str(b)], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    seen = json.loads(r.stdout)
    # lab 1 three times (two on the tour, one on a scenario that changes the end mass), lab 2 once
    assert seen["modules"] == 2
    assert seen["refs"] == [3, 3, 1, 3]
    # one MuJoCo model for the same world and plant; its own for a run whose scenario edits it
    assert seen["same_model_01"] and seen["same_model_02"] and not seen["same_model_03"]
    assert seen["after_stop_0"] == [2, 2]
    # lab 2's module outlives its last instance (kept, as a module no instance uses: a page that
    # runs the lab again loads nothing), and so do both once the worker holds no instance
    assert seen["after_stop_2"] == 2
    assert seen["after_close"] == 2


# -- the board configured in C ------------------------------------------------------------------------
@pytest.fixture(scope="module")
def configured():
    """A board of crslab's core (no firmware loaded: its cost unit is the native one, ns) given the
    settings of a run with a plant and options of its own."""
    from crslab._bindings import compiled_board

    plant = dataclasses.replace(PlantParams.defaults(), motor_gain=6.0, stall_nm=(12.0, 24.0, 36.0),
                                backemf_nm_s_per_rad=(0.6, 1.2, 1.8), drive_lag_s=0.004,
                                encoder_noise_counts=2.5)
    config = make_config(ROOT / "csrc" / "labs" / "lab1_kinematics.c", "tour", strict=True,
                         budget=30000, motor_board="piccolo", plant=plant, startup_delay=False,
                         rest_motor_rad=(0.1, -0.4, 0.3))
    board = compiled_board()
    sim = board.new_board(config.build.generation.id, board.pointer("crs_shared *", 0))
    board.configure(sim, board_settings(config))
    qpos = np.array([0.25, -0.5, 0.75])
    keep = [qpos]  # alive as long as the board points at it
    board.attach_plant(sim, {"qpos": board.pointer("double *", qpos.ctypes.data)})
    return board, sim, config, keep


def test_the_boards_counters_are_the_run_statistics_it_reports_by_name(configured):
    from crslab.worker.run_stats import BOARD_COUNTERS

    board, sim, _, _ = configured
    sim.lab_calls, sim.overflow_chars, sim.motor_board.cutouts, sim.safety_first_tick = 321, 77, 4, 4321
    read = board.counters(sim)
    assert list(read) == [*BOARD_COUNTERS, "tick", "motor_board_cutouts"]
    configured_as = {"cost_unit", "budget"}  # the board's configuration's, the rest its own
    assert {n: getattr(sim.config if n in configured_as else sim, n) for n in [*BOARD_COUNTERS, "tick"]} == {
        n: read[n] for n in [*BOARD_COUNTERS, "tick"]}
    assert (read["lab_calls"], read["overflow_chars"], read["motor_board_cutouts"]) == (321, 77, 4)
    assert read["safety_first_tick"] == 4321


def test_what_the_board_holds_is_what_the_run_asked(configured):
    _, sim, config, _ = configured
    c = constants
    held = sim.config  # what the run is configured with: set once
    assert held.generation == config.build.generation.id
    assert held.strict_nan == 1 and held.startup_ticks == 0
    assert held.motor_board == c.CRS_MOTOR_BOARD_PICCOLO
    # 30,000 instructions at 150 MHz take 0.2 ms: the native cost unit's budget is 200,000 ns
    assert held.cost_unit == c.CRS_COST_NS and held.budget == 200_000
    assert list(held.rest_motor_rad) == [0.1, -0.4, 0.3]
    # the drive in command units: N.m over the 6 N.m a unit gives
    assert list(held.drive.stall_units) == pytest.approx([2.0, 4.0, 6.0])
    assert list(held.drive.backemf_units_s_per_rad) == pytest.approx([0.1, 0.2, 0.3])
    assert held.drive.lag_s == 0.004
    assert list(sim.faults.noise_counts) == [2.5, 2.5, 2.5]
    assert (held.hand.kp_nm_per_rad, held.hand.max_nm) == (config.hand.kp, config.hand.max_nm)
    units = config.plant.sliding_units()
    for field in ("slide_pos_units", "slide_neg_units", "viscous_pos_units_s_per_rad"):
        assert list(getattr(held.friction, field)) == pytest.approx(list(units[field]))
    assert held.debug.break_when == 0 and held.time_lab == 1
    # the run's scope log is off: it logs no signals
    assert held.log_every_ticks == 0 and not config.log_signals


def test_the_board_applies_a_scenarios_event_itself(configured):
    board, sim, config, _ = configured
    c = constants
    from crslab.scenario.fault_events import EncoderGlitch, JointFault
    from crslab.scenario.hand_events import HandMove

    def apply(event):
        for fields in event_struct(c, event, np.zeros(3)):
            assert board.apply_event(sim, fields)

    sim.tick = 7000
    apply(HandMove(tick=7000, target_dh_rad=(0.1, 0.2, 0.3), duration_ticks=500))
    assert sim.hand.active == 1 and sim.hand.start_tick == 7000 and sim.hand.duration_ticks == 500
    assert list(sim.hand.start_dh_rad) == [0.25, -0.5, 0.75]  # from where the arm is
    assert list(sim.hand.target_dh_rad) == [0.1, 0.2, 0.3]
    apply(EncoderGlitch(tick=7000, counts=(5, 0, -3)))
    apply(EncoderGlitch(tick=7000, counts=(1, 2, 3)))  # two at one tick add up
    assert sim.faults.glitch_tick == 7000 and list(sim.faults.glitch_counts) == [6, 2, 0]
    apply(JointFault(tick=7000, fault="dead_motor", joints=(1, 3)))
    assert list(sim.faults.dead_motor) == [1, 0, 1]
    apply(JointFault(tick=7000, fault="dead_motor", joints=(3,), on=False))
    assert list(sim.faults.dead_motor) == [1, 0, 0]
    assert not board.apply_event(sim, {"kind": 99})


def test_a_board_logging_every_5th_tick_logs_those_rows_of_the_every_tick_log():
    """``log_every_ticks`` (crs_board_configure): the scope log keeps the ticks divisible by it,
    each row the same as a board logging every tick has for that tick (crslab serve's page: a row
    every 5 ms, as Simulink samples); a world's columns too."""
    full = make_config(ROOT / "csrc" / "labs" / "lab2_square_pid.c", "tour", log=True, world="contest")
    fifth = dataclasses.replace(full, log_every_ticks=5)
    worker = BoardClient()
    try:
        every, sparse = worker.open(full), worker.open(fifth)
        logs: dict[int, list] = {every.id: [], sparse.id: []}
        for until in (3, 250, 251, 503, 1000, 1012):  # chunks that start and end off the 5 ms grid
            worker.run([(every, until), (sparse, until)])
            for handle in (every, sparse):  # the rows wait in each instance's shared block
                logs[handle.id].append(handle.block.take_log(world=True))
    finally:
        worker.close()
    full_log = {k: np.concatenate([b[k] for b in logs[every.id]]) for k in logs[every.id][0]}
    sparse_log = {k: np.concatenate([b[k] for b in logs[sparse.id]]) for k in logs[sparse.id][0]}
    assert full_log["tick"][:, 0].tolist() == list(range(1012))
    assert sparse_log["tick"][:, 0].tolist() == list(range(0, 1012, 5))
    assert "egg_force" in sparse_log and set(sparse_log) == set(full_log)
    for name, column in full_log.items():
        assert np.array_equal(sparse_log[name], column[::5]), name
