"""A real client: GNU Octave with instrument-control runs scripts written in the course's style
(tests/octave: instrfind, the map parsed as parseMap does, serial / serialport, fwrite,
fread(s, N, 'float32'), fclose, delete) against ``crslab sim``'s SerialC, through crslab's Octave
compat files (crslab/host_tools/octave), in both generations: it reads a float, a 100-float
array of known values, writes a float and the lab prints the new value. One Octave run per
generation does every check (Octave starts slowly); this file judges what it printed against
values worked out by hand."""

import signal
import subprocess
import sys
from pathlib import Path

import pytest
from waiting import LineWatcher, wait_exit

from crslab.resources import path as resource_path

ROOT = Path(__file__).resolve().parents[1]
LABS = ROOT / "tests" / "labs"
CHECK = ROOT / "tests" / "octave" / "host_tools_check.m"
ARR, VAR = "Array Variable", "Float Variable"
GENERATIONS = {
    # lab, the folder the course's scripts look for the map in, the map's rows, the lab's print
    "A": (LABS / "host_tools_gen_a.c", "CRSRobotProject/Debug",
          [("theta1array", "0000c4c0", ARR), ("timearray", "0000c588", ARR), ("whattoprint", "0000c816", VAR),
           ("Kp1", "0000c818", VAR), ("samples", "0000c81a", VAR), ("matlabLock", "0000c81c", VAR)],
          "Kp1 40.00 simu 0 0"),
    "B": (LABS / "host_tools_gen_b.c", "CPU_FLASH",
          [("whattoprint", "0000d000", VAR), ("Kp1", "0000d002", VAR), ("samples", "0000d004", VAR),
           ("mode", "0000d006", VAR), ("theta1array", "0000e000", ARR), ("timearray", "0000e0c8", ARR)],
          "Kp1 40.00 simu 0 0 mode -2"),
}


def printed(lines: list[str], key: str) -> str:
    [line] = [line for line in lines if line.startswith(key + ": ")]
    return line[len(key) + 2:]


@pytest.mark.requires("octave")
@pytest.mark.parametrize("gen", sorted(GENERATIONS))
def test_octave_reads_and_writes_a_running_lab_as_the_courses_scripts_do(gen, tmp_path):
    lab, map_folder, map_rows, new_print = GENERATIONS[gen]
    (tmp_path / "matlab").mkdir()
    (tmp_path / map_folder).mkdir(parents=True)
    ports = tmp_path / "ports"
    sim = subprocess.Popen(
        [sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--scenario", "hands_off",
         "--no-startup-delay", "--serial-dir", str(ports), "--map", str(tmp_path / map_folder / "lab.map"),
         "--speed", "4", "--duration", "600", "--no-stdin", "--quiet"],
        cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        err = LineWatcher(sim.stderr, "crslab sim's stderr")
        out = LineWatcher(sim.stdout, "crslab sim's stdout")
        err.wait_for("SerialC .* linked at")
        octave = subprocess.Popen(
            ["octave", "--no-gui", "--no-window-system", "--norc", "--no-history", "--quiet", str(CHECK), gen,
             str(ports / "SerialC"), str(resource_path("octave"))],
            cwd=tmp_path / "matlab", stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        octave_out = LineWatcher(octave.stdout, "octave's stdout")
        octave_err = LineWatcher(octave.stderr, "octave's stderr")
        assert wait_exit(octave, "the Octave checks") == 0, octave_out.all() + octave_err.all()
        lines = octave_out.all().splitlines()
        out.wait_for(f"^{new_print}$")  # the write reached the lab, which printed it
        sim.send_signal(signal.SIGINT)
        assert wait_exit(sim, "Ctrl-C (SIGINT)") == 130
    finally:
        sim.kill()
    assert [tuple(line.split(" ", 3)[1:3]) + (line.split(" ", 3)[3],) for line in lines
            if line.startswith("map ")] == map_rows
    # a float: a double 1x1, as MATLAB's fread returns it
    assert printed(lines, "read whattoprint") == "1.25 double 1x1"
    assert printed(lines, "read Kp1") == "12.5"
    assert printed(lines, "read samples") == "100"
    # 100 floats: the times the lab sampled at, every 50 ms, in a ring that wrapped once at most
    size, *values = printed(lines, "read timearray").split()
    times = [float(v) for v in values]
    steps = [b - a for a, b in zip(times, times[1:])]
    assert size == "100x1" and len(times) == 100
    assert sorted(times) == [min(times) + 50 * k for k in range(100)] and set(steps) <= {50.0, -4950.0}
    # theta1array as Lab 1's template fills it: joint 1 rests at its encoder's zero
    size, *values = printed(lines, "read theta1array").split()
    assert size == "100x1" and [float(v) for v in values] == [0.0] * 100
    assert printed(lines, "after writing Kp1 40") == "40"
    assert printed(lines, "after writing whattoprint -2.5") == "-2.5"
    if gen == "A":
        assert printed(lines, "read matlabLock") == "1"  # every read sets it
    assert printed(lines, "error") == "MATLAB:VarNotFound: Variable name not found."
    assert lines[-1] == "done"
