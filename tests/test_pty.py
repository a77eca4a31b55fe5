"""--pty: the serial output on a pseudo-terminal, read by a real serial client (pyserial)."""

import os
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest
import serial
from waiting import GUARD_S, LineWatcher, join, wait_exit

from crslab.sinks.serial_pty import PtyError, PtySink

ROOT = Path(__file__).resolve().parents[1]


def read_until_closed(port):
    """Everything the port delivers until crslab closes it (reads then fail)."""
    got = b""
    while True:
        try:
            chunk = port.read(max(1, port.in_waiting))  # blocks until a byte arrives or the port closes
        except serial.SerialException:  # crslab closed the port at the end of the run
            return got
        if not chunk:
            raise AssertionError(f"nothing arrived on the port for {GUARD_S:g} s and it stayed open; "
                                 f"got so far: {got[-500:]!r}")
        got += chunk


def test_a_serial_client_on_the_pty_reads_exactly_the_transcript(tmp_path):
    link, transcript = tmp_path / "crs-tty", tmp_path / "run.bin"
    cmd = [sys.executable, "-m", "crslab", "sim", "--speed", "3", "--duration", "6.2",
           "--pty-link", str(link), "--pty-wait", "--transcript", str(transcript), "--no-stdin"]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        err = LineWatcher(proc.stderr, "crslab sim's stderr")
        [announced] = [line for line in err.wait_for("linked at") if "linked at" in line]
        assert f"(linked at {link})" in announced and "/dev/" in announced
        err.wait_for(f"waiting for a terminal on {link}")  # the run starts once the port is opened
        with serial.Serial(str(link), 115200, timeout=GUARD_S) as port:
            got = read_until_closed(port)
        assert wait_exit(proc, "the end of a 6.2 s run") == 0, err.all()
    finally:
        proc.kill()
    expected = transcript.read_bytes()
    assert expected.count(b"\n\r") == 15 and got == expected  # raw bytes: \n\r line ends untouched
    assert not os.path.lexists(link)  # the link goes with the port


def test_ctrl_c_while_waiting_for_a_terminal_ends_cleanly_and_removes_the_link(tmp_path):
    link = tmp_path / "crs-tty"
    cmd = [sys.executable, "-m", "crslab", "sim", "--pty-link", str(link), "--pty-wait", "--no-stdin"]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        out = LineWatcher(proc.stdout, "crslab sim's stdout")
        err = LineWatcher(proc.stderr, "crslab sim's stderr")
        err.wait_for("waiting for a terminal")
        assert os.path.islink(link)
        proc.send_signal(signal.SIGINT)
        assert wait_exit(proc, "Ctrl-C (SIGINT) while waiting for a terminal") == 130
    finally:
        proc.kill()
    assert out.all() == ""  # no tick ran
    assert err.all().strip().splitlines()[-1] == "crslab sim: interrupted"
    assert not os.path.lexists(link)


def test_bytes_sent_with_no_reader_are_dropped_and_writes_never_block(tmp_path):
    sink = PtySink(tmp_path / "tty")
    try:
        sink.on_serial(0, b"before anyone listens\n\r")
        with serial.Serial(str(tmp_path / "tty"), timeout=GUARD_S) as port:
            sink.on_serial(1, b"1.00 2.00 3.00\n\r")
            assert port.read(16) == b"1.00 2.00 3.00\n\r"  # returns once 16 bytes arrived
            sink.on_serial(2, b"left unread\n\r")
        sink.on_serial(3, b"nobody again\n\r")
        with serial.Serial(str(tmp_path / "tty"), timeout=GUARD_S) as port:
            sink.on_serial(4, b"fresh\n\r")
            assert port.read(7) == b"fresh\n\r"  # nothing stale from the last reader or the gap first

            def flood():  # a reader that never reads: 1 MB must not block the run
                for tick in range(2000):
                    sink.on_serial(tick, b"x" * 500)

            sent_before = sink.sent
            writer = threading.Thread(target=flood)
            writer.start()
            join(writer, "writing 1 MB to a terminal that never reads (a write blocked)")
            flooded = sink.sent - sent_before
            assert sink.dropped_slow > 0 and flooded < 1_000_000 and flooded + sink.dropped_slow == 1_000_000
        assert sink.dropped_unattached == len(b"before anyone listens\n\r") + len(b"nobody again\n\r")
    finally:
        sink.close()


def test_pty_link_refuses_to_replace_a_real_file(tmp_path):
    keep = tmp_path / "notes.txt"
    keep.write_text("mine")
    with pytest.raises(PtyError, match="not a symlink"):
        PtySink(keep)
    assert keep.read_text() == "mine"
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--duration", "1", "--pty-link",
                        str(keep)], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "not a symlink" in r.stderr
