"""--pty: the serial output on a pseudo-terminal, read by a real serial client (pyserial)."""

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
import serial

from crslab.sinks.serial_pty import PtyError, PtySink

ROOT = Path(__file__).resolve().parents[1]


def read_all(port, proc, timeout_s=60.0):
    """Everything the port delivers until crslab closes it."""
    got, end = b"", time.monotonic() + timeout_s
    while time.monotonic() < end:
        try:
            chunk = port.read(4096)
        except serial.SerialException:  # crslab closed the port at the end of the run
            break
        got += chunk
        if not chunk and proc.poll() is not None:
            break
    return got


def test_a_serial_client_on_the_pty_reads_exactly_the_transcript(tmp_path):
    link, transcript = tmp_path / "crs-tty", tmp_path / "run.bin"
    cmd = [sys.executable, "-m", "crslab", "sim", "--speed", "3", "--duration", "6.2",
           "--pty-link", str(link), "--transcript", str(transcript), "--no-stdin"]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        announced = proc.stderr.readline()  # printed before the first tick; the first print is at 4.1 s
        assert f"(linked at {link})" in announced and "/dev/" in announced
        with serial.Serial(str(link), 115200, timeout=0.3) as port:
            got = read_all(port, proc)
        assert proc.wait(60) == 0, proc.stderr.read()
    finally:
        proc.kill()
    expected = transcript.read_bytes()
    assert expected.count(b"\n\r") == 15 and got == expected  # raw bytes: \n\r line ends untouched
    assert not os.path.lexists(link)  # the link goes with the port


def test_bytes_sent_with_no_reader_are_dropped_and_writes_never_block(tmp_path):
    sink = PtySink(tmp_path / "tty")
    try:
        sink.on_serial(0, b"before anyone listens\n\r")
        with serial.Serial(str(tmp_path / "tty"), timeout=0.2) as port:
            sink.on_serial(1, b"1.00 2.00 3.00\n\r")
            assert port.read(100) == b"1.00 2.00 3.00\n\r"
            sink.on_serial(2, b"left unread\n\r")
        sink.on_serial(3, b"nobody again\n\r")
        with serial.Serial(str(tmp_path / "tty"), timeout=0.2) as port:
            sink.on_serial(4, b"fresh\n\r")
            assert port.read(100) == b"fresh\n\r"  # nothing stale from the last reader or the gap
            start = time.monotonic()
            for tick in range(2000):  # a reader that never reads: 1 MB never blocks the run
                sink.on_serial(tick, b"x" * 500)
            assert time.monotonic() - start < 2.0
            assert sink.dropped_slow > 0 and sink.sent < 1_000_000
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
