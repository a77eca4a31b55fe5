"""Live variables: `crslab vars` lists a lab's DATA_SECTION variables; typed get/set act on a running lab."""

import io
import json
import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from waiting import LineWatcher, join, wait_exit

from crslab.cli import main
from crslab.live.console import CommandError, VarConsole, parse_command
from crslab.run.api import make_config
from crslab.run.board_run import BoardRun
from crslab.sinks.memory import MemorySink

ROOT = Path(__file__).resolve().parents[1]
TYPES_LAB = ROOT / "tests" / "labs" / "watched_types.c"


def crslab(*args, **kw):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}  # the run must flush itself
    return subprocess.Popen([sys.executable, "-m", "crslab", *args], cwd=ROOT, env=env, text=True, **kw)


def test_vars_lists_scalars_and_arrays_with_type_length_and_initial_value(capsys):
    assert main(["vars", "--lab", str(TYPES_LAB)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == ["name", "address", "type", "length", "initial", "line"]
    rows = [re.split(r"\s{2,}", line.strip()) for line in lines[1:]]
    # Gen B: .my_vars from 0xd000 (a float, then two 16-bit ints), .my_arrs from 0xe000 (8 floats
    # take 16 words, then the longs at an even address)
    assert rows == [["gain", "0000d000", "float", "-", "2.5", "16"],
                    ["mode", "0000d002", "int", "-", "3", "18"],
                    ["flags", "0000d003", "Uint16", "-", "0", "20"],
                    ["call_log", "0000e000", "float", "8", "all 0", "22"],
                    ["limits", "0000e010", "long", "3", "{10, 20, 30}", "24"]]
    assert main(["vars", "--lab", str(TYPES_LAB), "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)
    assert [(v["name"], v["length"], v["section"]) for v in listed][3:] == [
        ("call_log", 8, ".my_arrs"), ("limits", 3, ".my_arrs")]


def test_vars_of_the_default_lab_and_bad_input(capsys, tmp_path):
    assert main(["vars"]) == 0
    assert [line.split()[0] for line in capsys.readouterr().out.splitlines()[1:]] == [
        "whattoprint", "theta1array", "theta2array"]
    assert main(["vars", "--lab", str(tmp_path / "missing.c")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no such lab file" in err
    plain = tmp_path / "plain.c"
    plain.write_text("void lab(void) {}\n")
    assert main(["vars", "--lab", str(plain)]) == 0
    assert "has no #pragma DATA_SECTION variables" in capsys.readouterr().err


def test_parse_command_accepts_the_documented_forms_and_explains_the_rest():
    assert parse_command("set call_log[7] -1e-3") == parse_command("SET  call_log[ 7 ]  -0.001")
    assert parse_command("list").verb == "list"
    for bad, why in [("", "commands:"), ("poke x 1", "unknown command 'poke'"), ("get", "needs a variable"),
                     ("set gain abc", "not a number"), ("set gain nan", "not a finite"),
                     ("get 3x", "not a variable name"), ("get a b", "one variable")]:
        with pytest.raises(CommandError, match=why):
            parse_command(bad)


def test_console_reads_and_writes_a_running_lab_between_ticks():
    config = make_config(TYPES_LAB, "hands_off", startup_delay=False)
    typed = io.StringIO("get call_log\nset gain 4\nset mode 7.6\nget limits[2]\nset limits[0] -5\n"
                        "get limits\nset mode 1e12\nset flags -1\nset gain[1] 2\nget call_log[8]\n"
                        "set call_log 1\nlist\n")
    replies = []
    console = VarConsole(config.build.watched, stream=typed, reply=replies.append)
    console.start()
    join(console._thread, "the console reading its typed lines")  # every command is queued
    out = MemorySink()
    with BoardRun(config) as sim:
        sim.run(150, out, controls=[console])
        sim.run(250, out)
    assert replies[0] == "call_log = [0 0.5 1 1.5 2 2.5 3 3.5]   (t = 0.150 s)"  # what the lab wrote
    assert replies[1:6] == ["gain = 4   (from t = 0.150 s on)", "mode = 8   (from t = 0.150 s on)",
                            "limits[2] = 30   (t = 0.150 s)", "limits[0] = -5   (from t = 0.150 s on)",
                            "limits = [-5 20 30]   (t = 0.150 s)"]
    # the same words as a scenario file's or a sweep's mistakes (crslab.lab.watched)
    assert replies[6] == "vars: 1e+12 does not fit mode, int in watched_types.c (-32768 to 32767)"  # 16 bits
    assert replies[7] == "vars: -1 does not fit flags, Uint16 in watched_types.c (0 to 65535)"
    assert replies[8] == "vars: gain is not an array in watched_types.c"
    assert replies[9] == "vars: call_log has 8 elements in watched_types.c: give an index 0..7"
    assert replies[10] == "vars: call_log has 8 elements in watched_types.c: give an index 0..7"
    assert replies[11].startswith("vars: gain  float  = 4\nvars: mode  int  = 8")  # current values
    # the lab prints `gain mode` every 100 calls: the writes show from the first print after them
    assert out.calls == [(0, b"2.50 3\n\r"), (100, b"2.50 3\n\r"), (200, b"4.00 8\n\r")]


def test_set_whattoprint_typed_during_a_run_changes_the_next_print_and_get_reads_arrays():
    # the run goes on until Ctrl-C, so the typed lines take effect whenever they arrive
    p = crslab("sim", "--speed", "4", "--duration", "600", "--scenario", "hands_off",
               stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        out, err = LineWatcher(p.stdout, "crslab sim's stdout"), LineWatcher(p.stderr, "crslab sim's stderr")
        out.wait_for(r"\d")  # the first print (4.1 s): the run is under way
        p.stdin.write("get theta2array\nset whattoprint 1\n")
        p.stdin.close()
        err.wait_for(r"^whattoprint = 1 ")
        out.wait_for("I love robotics")  # the first print after the write
        p.send_signal(signal.SIGINT)
        assert wait_exit(p, "Ctrl-C (SIGINT)") == 130
    finally:
        p.kill()
    err = err.all()
    got = re.search(r"^theta2array = \[(.*)\]   \(t = ([\d.]+) s\)$", err, re.MULTILINE)
    when = re.search(r"^whattoprint = 1   \(from t = ([\d.]+) s on\)$", err, re.MULTILINE)
    assert got and when, err
    tick = round(float(when.group(1)) * 1000)
    assert tick > 4100 and tick == round(float(got.group(2)) * 1000)
    # the lab saves theta2motor (the arm rests at -0.42 rad) every 50 calls from its first at 4.1 s,
    # in a ring of 100
    values = [float(v) for v in got.group(1).split()]
    saved = min(100, len(range(4100, tick, 50)))
    assert len(values) == 100 and values == [-0.42] * saved + [0.0] * (100 - saved)
    lines = out.all().splitlines()
    before = len(range(4100, tick, 500))  # prints (three lines each) before the write
    assert all(re.fullmatch(r"-?\d+\.\d\d -?\d+\.\d\d -?\d+\.\d\d", x) for x in lines[:3 * before]), lines
    assert lines[3 * before:] and set(lines[3 * before:]) == {"I love robotics"}


def test_the_worker_refuses_a_value_the_firmwares_type_cannot_hold_in_the_same_words():
    # a long is 32 bits in the firmware (as on the C28x), whatever the host's long is
    config = make_config(TYPES_LAB, "hands_off", startup_delay=False)
    with BoardRun(config) as sim:
        sim.run(1, MemorySink())
        with pytest.raises(KeyError, match=r"^'3e\+09 does not fit limits, long in watched_types.c "
                                           r"\(-2147483648 to 2147483647\)'$"):
            sim.set("limits", 3e9, index=0)
        with pytest.raises(KeyError, match="limits has 3 elements in watched_types.c: give an index 0..2"):
            sim.set("limits", 1)
        sim.set("limits", 2147483647, index=0)
        assert sim.get("limits") == [2147483647.0, 20.0, 30.0]
