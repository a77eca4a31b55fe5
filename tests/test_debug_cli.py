"""``crslab debug`` as a student meets it: bad input is one line before anything runs, a missing
gdb says how to install it, and on a terminal gdb owns the keyboard: quitting it at the first
stop lets the run go on to the end of the transcript ``crslab sim`` makes."""

from __future__ import annotations

import os
import pty
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from waiting import GUARD_S

from crslab.cli import main

LABS = Path(__file__).parent / "labs"
COUNTER = LABS / "debug_counter.c"
RUN = ["--lab", str(COUNTER), "--scenario", "hands_off", "--duration", "6"]


def crslab(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "crslab", *args], capture_output=True, text=True,
                          timeout=GUARD_S)


@pytest.mark.requires("gdb")  # the break is checked against the run once gdb was found
@pytest.mark.parametrize(("args", "line"), [
    (["--break-tick", "4099"], "--break-tick 4099: lab() is first called at tick 4100 (t = 4.1 s); "
                               "--no-startup-delay calls it from the first tick"),
    (["--break-time", "2"], "--break-time 2: lab() is first called at tick 4100 (t = 4.1 s); "
                            "--no-startup-delay calls it from the first tick"),
    (["--break-tick", "6000"], "--break-tick 6000: the run ends at tick 6000 (t = 6.0 s); give a longer "
                               "--duration"),
])
def test_a_break_outside_the_run_is_one_line(args, line):
    r = crslab("debug", "--lab", str(COUNTER), "--duration", "6", *args)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.strip() == f"crslab debug: {line}"


@pytest.mark.parametrize(("args", "line"), [
    (["--batch"], "--batch runs the --ex commands: give at least one"),
    (["--gdbserver", "0", "--ex", "print x"],
     "--ex and --batch drive gdb on this terminal; with --gdbserver, give commands in your debugger"),
])
def test_contradicting_debugger_options_are_one_line(args, line):
    r = crslab("debug", "--lab", str(COUNTER), "--duration", "6", *args)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.strip() == f"crslab debug: {line}"


@pytest.mark.requires("gdb")
def test_a_break_when_that_does_not_compile_names_itself():
    r = crslab("debug", "--lab", str(COUNTER), "--duration", "6", "--break-when", "mycount == nosuch")
    assert r.returncode == 2 and r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert any(line.startswith("--break-when:1:12: error: ") and "nosuch" in line for line in lines)
    assert lines[-1] == "crslab debug: debug_counter.c with --break-when 'mycount == nosuch' does not compile"


def test_a_missing_gdb_is_one_line_saying_how_to_install_it(monkeypatch, capsys):
    import shutil

    which = shutil.which
    monkeypatch.setattr(shutil, "which", lambda name, path=None: None if name == "gdb" else which(name, path))
    status = main(["debug", "--lab", str(COUNTER), "--duration", "6", "--quiet"])
    err = capsys.readouterr().err
    assert status == 2 and err == ("crslab debug: gdb is not installed: 'sudo apt install gdb' (Debian, "
                                   "Ubuntu, WSL) or 'sudo dnf install gdb' (Fedora)\n")


class Terminal:
    """A pseudo-terminal running a command, whose output a test waits on (guard timeout only)."""

    def __init__(self, argv: list[str]) -> None:
        self.pid, self.fd = pty.fork()
        if self.pid == 0:  # the child: the command on the terminal
            os.execv(argv[0], argv)
        self.text = ""
        self.closed = False
        self._cond = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        while True:
            try:
                data = os.read(self.fd, 4096)
            except OSError:  # the command ended: the terminal hung up
                data = b""
            with self._cond:
                if not data:
                    self.closed = True
                    self._cond.notify_all()
                    return
                self.text += data.decode(errors="replace")
                self._cond.notify_all()

    def wait_for(self, text: str) -> None:
        with self._cond:
            self._cond.wait_for(lambda: text in self.text or self.closed, GUARD_S)
            assert text in self.text, f"no {text!r} on the terminal: {self.text[-3000:]!r}"

    def type(self, keys: str) -> None:
        os.write(self.fd, keys.encode())

    def exit_status(self) -> int:
        with self._cond:
            self._cond.wait_for(lambda: self.closed, GUARD_S)
        _, status = os.waitpid(self.pid, 0)
        return os.waitstatus_to_exitcode(status)


@pytest.mark.requires("gdb")
def test_quitting_gdb_at_the_first_stop_lets_the_run_finish_alone(tmp_path):
    debugged, plain = tmp_path / "debugged.txt", tmp_path / "plain.txt"
    term = Terminal([sys.executable, "-m", "crslab", "debug", *RUN, "--transcript", str(debugged)])
    term.wait_for("(gdb) ")  # stopped in the first lab() call
    assert "crslab: tick 4100 (t = 4.100 s)" in term.text
    # said before the first tick: where the host's build differs from the board's
    assert "crslab debug: note: built natively: int is 32 bits here, 16 on the board" in term.text
    term.type("quit\n")
    term.wait_for("crslab debug: gdb has let go of the lab; it runs on to the end of the run "
                  "(Ctrl-C ends it)")
    assert term.exit_status() == 0
    assert "crslab debug: 6.000 s simulated in " in term.text
    s = crslab("sim", "--fast", "--quiet", *RUN, "--transcript", str(plain))
    assert s.returncode == 0 and debugged.read_bytes() == plain.read_bytes()


def test_a_debug_build_names_the_lab_where_it_is_now(tmp_path):
    """The same lab text in two folders gives two debug builds, each naming its own file for the
    debugger (a cached build of a copy elsewhere would send gdb to the other folder)."""
    from crslab.lab.build import build_lab

    text = (Path(__file__).parent / "labs" / "crash_after_5s.c").read_bytes()
    builds = []
    for folder in ("here", "there"):
        lab = tmp_path / folder / "lab.c"
        lab.parent.mkdir()
        lab.write_bytes(text)
        builds.append((lab, build_lab(lab, debug=True)))
    (here, a), (there, b) = builds
    assert a.shared_object != b.shared_object
    assert str(here).encode() in a.shared_object.read_bytes()
    assert str(there).encode() in b.shared_object.read_bytes()
    assert str(there).encode() not in a.shared_object.read_bytes()
