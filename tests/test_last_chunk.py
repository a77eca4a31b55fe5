"""The last chunk (#38): a run that ends early, any way, keeps every tick it ran in its scope log,
its CSV and what is read from them (the contest's card). The board writes each tick's scope row
into the shared block, which outlives the worker; the crslab process takes the rows after every
chunk and once more when the run ends. ``--fast`` runs in chunks of 20,000 ticks, so a run that
ends at tick 21,234 ends in the middle of its second chunk: before, its CSV had 20,000 rows."""

from __future__ import annotations

import csv
import re
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from waiting import LineWatcher, wait_exit

from crslab._bindings import constants
from crslab.run.pacing import FAST_SLICE_TICKS
from crslab.run.shared_block import SharedBlock

END_TICK = 21_234
"""The tick the lab stops the run at: in the second chunk of a ``--fast`` run."""
LAB = """/* Test lab: holds the arm (zero torque) and counts its calls; prints the count every second; at
 * the tick END_TICK, its call END_TICK - 4100, does what the test asks: writes through a null
 * pointer (a stray pointer), or waits for a flag nothing sets (a busy-wait). */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
long printcount = 0;
float *stray = 0;
volatile int ready = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 1000) == 0) {
        printcount = mycount;
        SWI_post(&SWI_printf);
    }
    if (mycount == END_CALL) {
        FAULT;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "call %ld\\n\\r", printcount);
}
"""
FAULTS = {"stray": "*stray = 1.0f", "hang": "while (!ready) { }"}


def write_lab(folder: Path, fault: str, end_tick: int = END_TICK) -> Path:
    lab = folder / f"{fault}.c"
    lab.write_text(LAB.replace("END_CALL", str(end_tick - 4100)).replace("FAULT", FAULTS[fault]))
    return lab


def csv_ticks(path: Path) -> np.ndarray:
    with path.open() as f:
        rows = list(csv.reader(f))
    assert rows[0][0] == "tick"
    return np.array([int(r[0]) for r in rows[1:]])


def sim(lab: Path, out: Path, *options: str) -> subprocess.CompletedProcess:
    command = [sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--scenario", "hands_off", "--fast",
               "--quiet", "--duration", "30", "--csv", str(out), *options]
    return subprocess.run(command, capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize(("fault", "options", "status"), [
    ("stray", (), 3),                                     # the firmware traps; its worker goes on
    ("hang", ("--deadline", "0.5"), 4),                   # interrupted by the worker's watchdog
    ("stray", ("--native",), 3),                          # the worker dies of SIGSEGV
], ids=["wasm-trap", "wasm-hang", "native-crash"])
def test_a_run_that_ends_mid_chunk_keeps_every_tick_in_its_csv(tmp_path, fault, options, status):
    assert FAST_SLICE_TICKS < END_TICK < 2 * FAST_SLICE_TICKS
    out = tmp_path / "run.csv"
    r = sim(write_lab(tmp_path, fault), out, *options)
    assert r.returncode == status, r.stderr
    assert f"at tick {END_TICK}" in r.stderr, r.stderr
    # every tick the board finished, the one it stopped in excluded, in order, once
    assert csv_ticks(out).tolist() == list(range(END_TICK))


def test_ctrl_c_in_the_middle_of_a_chunk_keeps_every_tick_the_worker_finished(tmp_path):
    out = tmp_path / "run.csv"
    lab = write_lab(tmp_path, "stray", end_tick=10**9)  # never stops by itself
    p = subprocess.Popen([sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--scenario", "hands_off",
                          "--fast", "--quiet", "--duration", "600", "--csv", str(out)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        stdout = LineWatcher(p.stdout, "crslab sim's stdout")
        stderr = LineWatcher(p.stderr, "crslab sim's stderr")
        stdout.wait_for(r"^call 15000")  # (tick 19,100) the first chunk was handed on: the second runs
        p.send_signal(signal.SIGINT)
        assert wait_exit(p, "Ctrl-C (SIGINT)") == 130
    finally:
        p.kill()
    said = stderr.all()
    ended = re.search(r"interrupted at t = (\d+\.\d{3}) s", said)
    assert ended, said
    end_tick = round(float(ended.group(1)) * 1000)
    assert end_tick >= FAST_SLICE_TICKS  # killed in the second chunk (or, on a slow machine, as it began)
    assert csv_ticks(out).tolist() == list(range(end_tick))


def test_the_shared_blocks_scope_rows_are_read_within_its_bounds():
    """A native lab may scribble on the block: a count out of range reads at most the block's rows."""
    block = SharedBlock.new()
    try:
        log = block.view.log
        log.count = 3
        log.tick[0:3] = [7, 8, 9]
        for i in range(3 * 3):
            log.enc_rad[i] = i / 10
        rows = block.take_log(world=False)
        assert rows["tick"].tolist() == [[7], [8], [9]] and rows["enc_rad"][2].tolist() == [0.6, 0.7, 0.8]
        assert log.count == 0 and block.take_log(world=False)["tick"].shape == (0, 1)  # taken once
        log.count = 10**12
        assert block.take_log(world=True)["tick"].shape == (constants.CRS_LOG_CAPACITY, 1)
        log.count = -5
        rows = block.take_log(world=True)
        assert rows["tick"].shape == (0, 1) and rows["peg_tip"].shape == (0, 3)
    finally:
        block.close()


def test_a_contest_run_that_traps_keeps_every_tick_for_its_card(tmp_path):
    """What the contest's card is scored from: the run's log, the world's columns and all."""
    from crslab.run.api import simulate

    run = simulate(write_lab(tmp_path, "stray"), "hands_off", duration_s=30, log=True, world="contest")
    assert run.status == "crashed" and run.end_tick == END_TICK
    assert run.log["tick"][:, 0].tolist() == list(range(END_TICK))
    assert all(len(run.log[name]) == END_TICK for name in ("egg_force", "scale_g", "peg_tip"))
