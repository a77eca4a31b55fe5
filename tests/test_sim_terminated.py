"""SIGTERM and SIGHUP on a running ``crslab sim`` end it as Ctrl-C does: one line saying when,
what was printed kept, and nothing left behind (the --serial-dir links and map, the --pty-link),
with the shell's exit status for the signal."""

import signal
import subprocess
import sys
from pathlib import Path

import pytest
from waiting import LineWatcher, wait_exit

LAB = Path(__file__).parent / "labs" / "host_tools_gen_a.c"


def start_sim(*args, cwd):
    return subprocess.Popen([sys.executable, "-m", "crslab", "sim", "--lab", str(LAB), "--scenario",
                             "hands_off", "--no-startup-delay", "--duration", "600", "--no-stdin", *args],
                            cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)


@pytest.mark.parametrize("signum, status", [(signal.SIGTERM, 143), (signal.SIGHUP, 129)])
def test_a_terminated_run_removes_its_serial_links_and_map_and_says_when(tmp_path, signum, status):
    ports = tmp_path / "ports"
    sim = start_sim("--serial-dir", ports, "--transcript", "run.txt", cwd=tmp_path)
    try:
        out = LineWatcher(sim.stdout, "crslab sim's stdout")
        err = LineWatcher(sim.stderr, "crslab sim's stderr")
        out.wait_for(r"^Kp1 ", count=2)  # running, at real time, its ports and map in place
        assert sorted(p.name for p in ports.iterdir()) == ["SerialA", "SerialB", "SerialC",
                                                           "host_tools_gen_a.map"]
        sim.send_signal(signum)
        assert wait_exit(sim, signal.Signals(signum).name) == status
        stderr = err.all().decode()
    finally:
        sim.kill()
    name = signal.Signals(signum).name
    assert f"crslab sim: terminated ({name}) at t = " in stderr, stderr
    assert list(ports.iterdir()) == []  # no links, no map: a later 'serial read --dir' finds none
    assert b"Kp1 " in (tmp_path / "run.txt").read_bytes()  # what was printed is kept


def test_a_terminated_run_removes_its_pty_link(tmp_path):
    sim = start_sim("--pty-link", "tty", cwd=tmp_path)
    try:
        err = LineWatcher(sim.stderr, "crslab sim's stderr")
        out = LineWatcher(sim.stdout, "crslab sim's stdout")
        out.wait_for(r"^Kp1 ")
        assert (tmp_path / "tty").is_symlink()
        sim.send_signal(signal.SIGTERM)
        assert wait_exit(sim, "SIGTERM") == 143
        assert "terminated (SIGTERM) at t = " in err.all().decode()
    finally:
        sim.kill()
    assert not (tmp_path / "tty").is_symlink()


def test_terminated_before_the_run_is_one_line_too(tmp_path):
    """A SIGTERM while the worker starts (here: while the lab waits for a terminal) is one line."""
    sim = start_sim("--pty-link", "tty", "--pty-wait", cwd=tmp_path)
    try:
        err = LineWatcher(sim.stderr, "crslab sim's stderr")
        err.wait_for("waiting")
        sim.send_signal(signal.SIGTERM)
        assert wait_exit(sim, "SIGTERM") == 143
        lines = err.all().decode().splitlines()
    finally:
        sim.kill()
    assert any(line.startswith("crslab sim: terminated (SIGTERM)") for line in lines), lines
    assert not any("Traceback" in line for line in lines)
    assert not (tmp_path / "tty").is_symlink()
