"""``crslab sim`` as a student runs it: output, transcript, determinism, and bad input."""

import signal
import subprocess
import sys
from pathlib import Path

from waiting import LineWatcher, wait_exit

LABS = Path(__file__).parent / "labs"


def crslab(*args, timeout=120):
    return subprocess.run([sys.executable, "-m", "crslab", *args], capture_output=True, timeout=timeout)


def test_transcript_is_exact_and_stdout_is_tera_term_view(tmp_path):
    t = tmp_path / "t.txt"
    r = crslab("sim", "--fast", "--duration", "5", "--transcript", str(t))
    assert r.returncode == 0, r.stderr
    raw = t.read_bytes()
    assert raw.count(b"\n\r") == 6 and raw.startswith(b"0.00 -24.06 13.75\n\r")
    assert r.stdout == raw.replace(b"\n\r", b"\n")


def test_same_run_is_byte_identical_at_fast_and_speed_5(tmp_path):
    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    ra = crslab("sim", "--fast", "--duration", "10", "--transcript", str(a))
    rb = crslab("sim", "--speed", "5", "--duration", "10", "--transcript", str(b))
    assert ra.returncode == rb.returncode == 0
    assert a.read_bytes() == b.read_bytes() and len(a.read_bytes()) > 300


def one_line(stderr: bytes) -> str:
    lines = stderr.decode().strip().splitlines()
    return lines[-1]


def test_missing_lab_file():
    r = crslab("sim", "--lab", "no_such_lab.c")
    assert r.returncode == 2 and r.stdout == b""
    assert r.stderr.decode().strip() == "crslab sim: no_such_lab.c: no such lab file"


def test_compile_error_shows_gcc_diagnostics_at_the_users_line():
    r = crslab("sim", "--lab", str(LABS / "does_not_compile.c"))
    assert r.returncode == 2 and r.stdout == b""
    err = r.stderr.decode()
    assert "does_not_compile.c:9:" in err  # gcc names the user's file and line
    assert one_line(r.stderr) == "crslab sim: does_not_compile.c does not compile"
    assert "Traceback" not in err


def test_bad_option_and_bad_value():
    r = crslab("sim", "--warp", "9")
    assert r.returncode == 2 and len(r.stderr.decode().strip().splitlines()) == 1
    r = crslab("sim", "--speed", "-1")
    assert r.returncode == 2 and "--speed" in r.stderr.decode()
    r = crslab("sim", "--scenario", "nowhere")
    assert r.returncode == 2 and one_line(r.stderr).startswith("crslab sim: nowhere: no such scenario")


def test_ctrl_c_stops_cleanly_and_keeps_what_was_printed(tmp_path):
    t = tmp_path / "t.txt"
    cmd = [sys.executable, "-m", "crslab", "sim", "--no-startup-delay", "--transcript", str(t)]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        out, err = LineWatcher(p.stdout, "crslab sim's stdout"), LineWatcher(p.stderr, "crslab sim's stderr")
        out.wait_for(r"\d", count=6)  # real time: prints at 0, 0.5, 1.0 ... s; the sixth is at 2.5 s
        p.send_signal(signal.SIGINT)
        assert wait_exit(p, "Ctrl-C (SIGINT)") == 130
    finally:
        p.kill()
    assert err.all().decode().strip().splitlines()[-1].startswith("crslab sim: interrupted at t = ")
    raw = t.read_bytes()
    assert raw.count(b"\n\r") >= 6
    assert out.all() == raw.replace(b"\n\r", b"\n")


def test_a_ctrl_c_while_a_chunk_goes_to_the_sinks_waits_until_every_sink_has_it():
    from crslab.run.api import make_config
    from crslab.run.board_run import BoardRun
    from crslab.run.pacing import FAST_SLICE_TICKS
    from crslab.run.status import RunStatus
    from crslab.sinks.memory import MemorySink
    from crslab.sinks.sink import FanOut

    class CtrlCAtSecondLine(MemorySink):  # as if Ctrl-C were pressed between the two sinks
        def on_serial(self, tick, data):
            super().on_serial(tick, data)
            if len(self.sent) == 2:  # the second tick whose bytes left the board
                signal.raise_signal(signal.SIGINT)

    first, second = CtrlCAtSecondLine(), MemorySink()
    with BoardRun(make_config(startup_delay=False)) as sim:
        result = sim.run(2 * FAST_SLICE_TICKS, FanOut([first, second]))
    assert result.status is RunStatus.INTERRUPTED
    # the whole first chunk reached both sinks, once: a print (three lines) every 500 ticks
    assert first.sent == second.sent and first.calls == second.calls
    assert [t for t, _ in first.calls] == [t for t in range(0, FAST_SLICE_TICKS, 500) for _ in range(3)]
