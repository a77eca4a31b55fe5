"""``crslab debug`` under a real gdb: the break at a tick, a time or a condition stops inside
``lab()`` with the lab's globals as they are at that tick; crashes stop at the lab's line; an
IDE attaches through gdbserver with the documented launch.json; a run continued to its end
prints exactly what ``crslab sim`` prints.

Every expected value is derived independently of the debugger: the counter a test lab
increments once per ``lab()`` call from the startup gate, the plain run's CSV, the line of the
lab file that holds the faulting statement.
"""

from __future__ import annotations

import csv
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from waiting import GUARD_S, LineWatcher, wait_exit

from crslab.worker.config import STARTUP_TICKS

LABS = Path(__file__).parent / "labs"
COUNTER = LABS / "debug_counter.c"
DOCS = Path(__file__).parent.parent / "docs" / "debugging.md"
RUN = ["--lab", str(COUNTER), "--scenario", "hands_off", "--duration", "6"]
"""The run of every test on the counter lab: no hand moves, joint 1 turned by the lab alone."""


def crslab(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "crslab", *args], capture_output=True, text=True,
                          timeout=GUARD_S)


def plain_run(*outputs: str) -> None:
    """``crslab sim`` of :data:`RUN`, writing ``outputs`` (``--transcript F``, ``--csv F``)."""
    s = crslab("sim", "--fast", "--quiet", *RUN, *outputs)
    assert s.returncode == 0, s.stderr


def gdb_values(stdout: str) -> list[str]:
    """What gdb's print commands printed, in order (``$1 = 900`` gives ``900``)."""
    return re.findall(r"^\$\d+ = (.*)$", stdout, re.MULTILINE)


def line_of(path: Path, text: str) -> int:
    """The 1-based line of ``path`` holding ``text`` (the faulting statement of a test lab)."""
    lines = path.read_text().splitlines()
    found = [i + 1 for i, line in enumerate(lines) if text in line]
    assert len(found) == 1, found
    return found[0]


@pytest.mark.requires("gdb")
def test_break_tick_stops_in_lab_with_that_ticks_globals_and_continues_to_the_plain_transcript(tmp_path):
    """On the tour, whose hand starts moving the arm at the break's very tick (5.0 s)."""
    debugged, plain = tmp_path / "debugged.txt", tmp_path / "plain.txt"
    tour = ["--lab", str(COUNTER), "--scenario", "tour", "--duration", "7"]
    r = crslab("debug", *tour, "--break-tick", "5000", "--transcript", str(debugged), "--batch",
               "--ex", "print mycount", "--ex", "print $tick",
               "--ex", "break lab", "--ex", "continue", "--ex", "print mycount", "--ex", "print $tick",
               "--ex", "delete", "--ex", "continue")
    assert r.returncode == 0, r.stderr
    # lab() is first called at the startup gate and counts its calls: on entry at tick 5000 it has
    # been called for ticks STARTUP_TICKS..4999; one tick later once more
    assert gdb_values(r.stdout) == [str(5000 - STARTUP_TICKS), "5000", str(5001 - STARTUP_TICKS), "5001"]
    assert "crslab: tick 5000 (t = 5.000 s)" in r.stdout
    assert "lab (theta1motor=" in r.stdout and f"{COUNTER.name}:" in r.stdout  # stopped inside lab()
    assert ("crslab debug: t = 5.0 s: hand to motor (0.00, 0.00, 0.00) = DH (0.00, -90.00, 90.00) deg over 2"
            in r.stderr)
    s = crslab("sim", "--fast", "--quiet", *tour, "--transcript", str(plain))
    assert s.returncode == 0, s.stderr
    assert debugged.read_bytes() == plain.read_bytes()  # the hand moved the arm from its tick, as in sim
    assert plain.read_bytes().count(b"\n\r") == 6  # what the lab printed after the break is there too


@pytest.mark.requires("gdb")
def test_break_when_stops_at_the_first_tick_where_the_condition_holds_per_the_runs_csv(tmp_path):
    plain_csv, debugged_csv = tmp_path / "plain.csv", tmp_path / "debugged.csv"
    plain_run("--csv", str(plain_csv))
    with open(plain_csv) as f:
        rows = list(csv.DictReader(f))
    ticks = np.array([int(row["tick"]) for row in rows])
    enc1 = np.array([float(row["theta1motor [rad]"]) for row in rows], dtype=np.float32)  # as lab() got it
    # theta1_seen holds what lab() was handed at the previous call: the condition first holds when
    # lab() begins at the tick after the first one (with lab() called) whose angle exceeds 0.5
    crossing = int(np.flatnonzero((enc1 > np.float32(0.5)) & (ticks >= STARTUP_TICKS))[0])
    expected = int(ticks[crossing]) + 1
    assert enc1[crossing - 1] <= 0.5 < enc1[crossing]

    r = crslab("debug", *RUN, "--break-when", "theta1_seen > 0.5", "--csv", str(debugged_csv), "--batch",
               "--ex", "print $tick", "--ex", "print theta1_seen", "--ex", "print mycount")
    assert r.returncode == 0, r.stderr
    tick, seen, count = gdb_values(r.stdout)
    assert int(tick) == expected
    assert np.float32(seen) == enc1[crossing]
    assert int(count) == expected - STARTUP_TICKS
    assert (f"crslab debug: --break-when 'theta1_seen > 0.5' holds at tick {expected} "
            f"(t = {expected / 1000:.3f} s)") in r.stderr
    # the CSV sink went on once gdb let the lab go: the same rows as the plain run's
    assert debugged_csv.read_bytes() == plain_csv.read_bytes()


@pytest.mark.requires("gdb")
def test_break_when_on_lab_errors_flag_stops_where_the_runs_csv_first_shows_the_envelope_left(tmp_path):
    """The issue's own example, on crslab's Lab 1 and the tour (whose DH-zero pose lies outside
    the safety envelope): the flag the framework computes at a tick is what lab() gets next."""
    plain_csv = tmp_path / "plain.csv"
    tour = ["--scenario", "tour", "--duration", "12"]
    s = crslab("sim", "--fast", "--quiet", *tour, "--csv", str(plain_csv))
    assert s.returncode == 0, s.stderr
    with open(plain_csv) as f:
        rows = [(int(row["tick"]), int(row["safety [0/1]"])) for row in csv.DictReader(f)]
    expected = next(tick for tick, safety in rows if safety == 1 and tick >= STARTUP_TICKS) + 1
    r = crslab("debug", *tour, "--break-when", "error == 1", "--quiet", "--batch",
               "--ex", "print $tick", "--ex", "print error")
    assert r.returncode == 0, r.stderr
    assert gdb_values(r.stdout) == [str(expected), "1"]


@pytest.mark.requires("gdb")
def test_debug_on_crash_stops_at_the_segfaulting_line_then_ends_as_sim_does():
    lab = LABS / "crash_after_5s.c"
    line = line_of(lab, "*gainptr = 2.0f;")
    r = crslab("debug", "--lab", str(lab), "--debug-on-crash", "--duration", "6", "--quiet", "--batch",
               "--ex", "print mycount", "--ex", "info line")
    assert r.returncode == 3, r.stderr
    assert "Program received signal SIGSEGV" in r.stdout
    assert re.search(rf"in lab \(.*\) at .*{lab.name}:{line}\n{line}\t\s*\*gainptr = 2\.0f;", r.stdout)
    assert gdb_values(r.stdout) == ["1000"]  # its 1001st call writes through the null pointer
    assert f'Line {line} of "{lab}"' in r.stdout
    assert r.stderr.strip().splitlines()[-1] == (
        "crslab debug: crash_after_5s.c crashed (SIGSEGV) in lab() at tick 5100 (t = 5.100 s)")


@pytest.mark.requires("gdb")
def test_debug_on_crash_with_strict_stops_at_the_line_that_makes_the_nan():
    lab = LABS / "faulty" / "nan_torque.c"
    line = line_of(lab, "*tau2 = dtheta / dt;")
    r = crslab("debug", "--lab", str(lab), "--strict", "--debug-on-crash", "--duration", "6", "--quiet",
               "--batch", "--ex", "print mycount")
    assert r.returncode == 3, r.stderr
    assert ("crslab: the lab stopped at tick 5099 (t = 5.099 s): an invalid operation made a NaN (SIGFPE)"
            in r.stdout)
    assert re.search(rf"in lab \(.*\) at .*{lab.name}:{line}\n", r.stdout)
    assert gdb_values(r.stdout) == ["999"]


@pytest.mark.requires("gdb")
def test_debug_on_crash_with_sanitize_stops_at_the_labs_frame_and_names_the_finding():
    lab = LABS / "faulty" / "off_by_one_template.c"
    line = line_of(lab, "theta1array[arrayindex] = theta1motor;")
    r = crslab("debug", "--lab", str(lab), "--sanitize", "--debug-on-crash", "--duration", "9.2", "--quiet",
               "--batch", "--ex", "print arrayindex")
    assert r.returncode == 3, r.stderr
    assert "Program received signal SIGABRT" in r.stdout  # deep in the sanitizer's runtime ...
    assert "AddressSanitizer: global-buffer-overflow" in r.stdout
    assert re.search(rf"#\d+ .* in lab \(.*\) at .*{lab.name}:{line}\n", r.stdout)  # ... shown at the lab's
    assert gdb_values(r.stdout) == ["100"]  # one past the end of theta1array[100]
    assert "AddressSanitizer: global-buffer-overflow (WRITE of size 4)" in r.stderr.strip().splitlines()[-1]


def documented_launch_json() -> dict:
    """The VS Code configuration docs/debugging.md gives (the first ```json block)."""
    block = re.search(r"```json\n(.*?)```", DOCS.read_text(), re.DOTALL)
    assert block is not None
    return json.loads(block.group(1))["configurations"][0]


@pytest.mark.requires("gdb", "gdbserver")
def test_an_ide_attaches_through_gdbserver_with_the_documented_launch_json(tmp_path):
    """What VS Code's cppdbg sends gdb for the documented launch.json, over gdb's MI: the setup
    commands, the program, ``-target-select remote`` at the address, continue; it stops in lab()
    at the break tick with the tick's globals; detaching lets the run finish as crslab sim's."""
    config = documented_launch_json()
    assert config["type"] == "cppdbg" and config["MIMode"] == "gdb"
    debugged, plain = tmp_path / "debugged.txt", tmp_path / "plain.txt"
    run = subprocess.Popen([sys.executable, "-m", "crslab", "debug", *RUN, "--break-tick", "5000",
                            "--gdbserver", "0", "--transcript", str(debugged)],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        err = LineWatcher(run.stderr, "crslab debug's stderr")
        held = re.search(r"lab\(\) is held before tick 5000 .* gdbserver listens on localhost:(\d+): "
                         r"attach your IDE \(docs/debugging.md; its program is (\S+)\)",
                         err.wait_for(r"lab\(\) is held before tick 5000")[-1])
        assert held is not None
        port, program = held.group(1), held.group(2)
        address = config["miDebuggerServerAddress"].replace("3333", port)
        gdb = subprocess.Popen([config.get("miDebuggerPath", "gdb"), "--interpreter=mi2", "-nx", "-q"],
                               stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1)
        out = LineWatcher(gdb.stdout, "gdb's MI output")

        def mi(command: str, reply: str = r"^\^(done|running|connected)") -> re.Match:
            """Send an MI command; wait for the first line matching ``reply`` after it."""
            before = sum(1 for line in out.lines if re.search(reply, line))
            gdb.stdin.write(command + "\n")
            gdb.stdin.flush()
            match = re.search(reply, out.wait_for(reply, before + 1)[-1])
            assert match is not None
            return match

        for setup in config["setupCommands"]:
            text = setup["text"].replace("\\", "\\\\").replace('"', '\\"')
            mi(f'-interpreter-exec console "{text}"', r"^\^(done|error)")
        mi(f"-file-exec-and-symbols {program}")
        mi(f"-target-select remote {address}", r"^\^connected")
        mi("-exec-continue", r'^\*stopped,reason="breakpoint-hit".*func="lab"')
        value = r'^\^done,value="(.*)"'
        assert mi("-data-evaluate-expression mycount", value).group(1) == str(5000 - STARTUP_TICKS)
        assert mi("-data-evaluate-expression crs_tick", value).group(1) == "5000"
        mi("-target-detach")
        mi("-gdb-exit", r"^\^exit")
        assert wait_exit(gdb, "-gdb-exit") == 0
        assert wait_exit(run, "gdb detached from the lab") == 0, err.all()
    finally:
        run.kill()
    plain_run("--transcript", str(plain))
    assert debugged.read_bytes() == plain.read_bytes()


@pytest.mark.requires("gdb")
def test_the_hang_watchdog_never_fires_while_gdb_holds_the_lab(tmp_path):
    """Held at the break for ten times ``--deadline`` (the user at gdb's prompt: gdb runs
    ``sleep`` there; this is the stimulus, not a synchronization, and a slower machine only
    holds longer), the run still ends ok with the plain run's transcript: only the debugger
    decides how long lab() may take while it holds it."""
    debugged, plain = tmp_path / "debugged.txt", tmp_path / "plain.txt"
    r = crslab("debug", *RUN, "--deadline", "0.05", "--break-tick", "5000", "--transcript", str(debugged),
               "--batch", "--ex", "shell sleep 0.5", "--ex", "print mycount",
               "--ex", "continue")
    assert r.returncode == 0, r.stderr
    assert "hung" not in r.stderr
    assert gdb_values(r.stdout) == [str(5000 - STARTUP_TICKS)]
    plain_run("--transcript", str(plain))
    assert debugged.read_bytes() == plain.read_bytes()


@pytest.mark.requires("gdb")
def test_bt_shows_the_lab_and_the_framework_only_and_gdb_keeps_its_chatter_off_stdout():
    """``bt`` stops at the framework's loop (crs_board_run), not ~180 frames of CPython and cffi
    below it (``bt -no-filters`` still shows them); stdout carries what the lab printed and the
    user's commands' output, not gdb's thread-library notices."""
    r = crslab("debug", *RUN, "--break-tick", "5000", "--batch", "--ex", "bt", "--ex", "echo --all--\\n",
               "--ex", "bt -no-filters")
    assert r.returncode == 0, r.stderr
    filtered, everything = r.stdout.split("--all--\n")
    frames = re.findall(r"^#(\d+)\s+(?:0x[0-9a-f]+ in )?(\w+) ", filtered, re.MULTILINE)
    # the lab, the framework's call of it as the lab defines it (compiled after the lab, in its
    # unit: crslab/lab/entry_points.py), the firmware's entry (csrc/firmware/firmware.c), the
    # board's port to it (csrc/board/firmware_native.c), the framework's tick and the chunk's loop of
    # ticks (csrc/board/tick.c)
    assert [name for _, name in frames] == ["lab", "crs_lab_call_lab", "crs_fw_lab", "crs_fw_call_lab",
                                            "lab_tick", "framework_tick", "run_ticks", "crs_board_run"]
    assert frames[-1][0] == "7"
    unfiltered = re.findall(r"^#\d+\s+(?:0x[0-9a-f]+ in )?(\w+) ", everything, re.MULTILINE)
    assert len(unfiltered) > 20 and any(name.startswith("_PyEval") for name in unfiltered)
    assert "libthread_db" not in r.stdout and "Thread debugging" not in r.stdout
    assert r.stdout.splitlines()[0] == "count 1 theta1 0.000"  # the lab's first line comes first
