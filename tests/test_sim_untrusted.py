"""Untrusted lab code: crashes, hangs, exits, NaNs, memory errors and floods are diagnosed in
one line with the right status, the transcript printed before the fault is kept, and no
process is left behind, on the WebAssembly board (the default) and on the native one (--native).

The WebAssembly firmware names the lab's line (its trap's backtrace, or the check it was compiled
with); a native one dies by a signal, which names only the function."""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from crslab.run.api import make_config, simulate
from crslab.run.inprocess import run_in_process

FAULTY = Path(__file__).parent / "labs" / "faulty"
BEFORE_FAULT = b"count 1 theta1 0.00\n\rcount 501 theta1 0.00\n\rcount 1001 theta1 0.00\n\r"


def sim(lab, tmp_path, *extra, timeout=120, defines=None, preexec_fn=None):
    """``crslab sim`` on a copy of the faulty lab in ``tmp_path`` (a path no other test runs), each
    of its ``#define NAME`` lines named in ``defines`` given that value."""
    transcript = tmp_path / "transcript.txt"
    text = (FAULTY / lab).read_text()
    for name, value in (defines or {}).items():
        text, found = re.subn(rf"^#define {name} .*$", f"#define {name} {value}", text, flags=re.M)
        assert found == 1, f"{lab} has no #define {name}"
    (tmp_path / lab).write_text(text)
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--lab", str(tmp_path / lab),
                        "--duration", "8", "--transcript", str(transcript), *extra],
                       capture_output=True, timeout=timeout, preexec_fn=preexec_fn)
    return r, transcript.read_bytes()


def last_line(r):
    return r.stderr.decode().strip().splitlines()[-1]


def no_process_left(lab: Path) -> bool:
    """No process runs ``lab`` once crslab has exited: it stops and reaps its worker before exiting."""
    found = subprocess.run(["pgrep", "-f", str(lab)], capture_output=True, text=True)
    return found.stdout.strip() == ""


AT_5123 = "in lab() at tick 5123 (t = 5.123 s)"


@pytest.mark.parametrize("lab, board, diagnosis", [
    ("segfault_in_lab.c", "wasm",
     f"segfault_in_lab.c used a NULL pointer (its address was 0) at segfault_in_lab.c:25 {AT_5123}"),
    ("segfault_in_lab.c", "native", f"segfault_in_lab.c crashed (SIGSEGV) {AT_5123}"),
    ("abort_in_lab.c", "wasm",
     f"abort_in_lab.c called abort() (or an assertion failed) at abort_in_lab.c:24 {AT_5123}"),
    ("abort_in_lab.c", "native", f"abort_in_lab.c crashed (SIGABRT) {AT_5123}"),
    ("stack_overflow_in_lab.c", "wasm",
     f"stack_overflow_in_lab.c overflowed its call stack (runaway recursion) at stack_overflow_in_lab.c:12 "
     f"{AT_5123}"),
    ("stack_overflow_in_lab.c", "native", f"stack_overflow_in_lab.c crashed (SIGSEGV) {AT_5123}"),
    ("exit_in_lab.c", "wasm", f"exit_in_lab.c called exit(0) at exit_in_lab.c:24 {AT_5123}"),
    ("exit_in_lab.c", "native", f"exit_in_lab.c called exit(0) {AT_5123}"),
])
def test_crash_is_one_line_and_keeps_the_transcript(lab, board, diagnosis, tmp_path):
    r, transcript = sim(lab, tmp_path, *(["--native"] if board == "native" else []))
    assert r.returncode == 3
    assert last_line(r) == f"crslab sim: {diagnosis}"
    assert transcript == BEFORE_FAULT
    assert r.stdout == BEFORE_FAULT.replace(b"\n\r", b"\n")
    assert b"Traceback" not in r.stderr
    assert no_process_left(tmp_path / lab)


@pytest.mark.parametrize("board", ["wasm", "native"])
@pytest.mark.parametrize("lab, func, tick, loop", [("hang_in_lab.c", "lab()", 5123, 24),
                                                   ("hang_in_printing.c", "printing()", 5100, 31)])
def test_hang_is_stopped_and_named(lab, func, tick, loop, board, tmp_path):
    # (sim's timeout guards against no stop at all)
    r, transcript = sim(lab, tmp_path, "--deadline", "0.5", *(["--native"] if board == "native" else []))
    assert r.returncode == 4
    # WebAssembly: where the firmware was when it was stopped, the busy loop's own line (wasmtime
    # names no line for a loop's head: the firmware's line table does)
    where = f"; it was at {lab}:{loop} in {func}" if board == "wasm" else ""
    assert last_line(r) == (f"crslab sim: {lab} hung: {func} did not return within 0.5 s "
                            f"at tick {tick} (t = {tick / 1000:.3f} s){where}")
    summary = r.stderr.decode().strip().splitlines()[-2]
    if board == "wasm":  # (a native worker that hung is killed with its counts)
        assert re.search(r"lab\(\) x\d+: mean [\d,.]+ instructions, max [\d,.]+ instructions \(tick \d+\); ",
                         summary), summary
        if func == "lab()":  # the call that hung was never measured: no "0 over the budget"
            assert summary.endswith(f"; the call at tick {tick} did not return (not counted above)"), summary
        else:
            assert re.search(r"; 0 over the budget of 75,000 instructions$", summary), summary
    assert transcript == BEFORE_FAULT
    assert no_process_left(tmp_path / lab)


def test_a_native_runs_summary_gives_each_number_its_unit(tmp_path):
    r, _ = sim("nan_torque.c", tmp_path, "--native", "--duration", "4.3")
    assert r.returncode == 0, r.stderr
    summary = next(line for line in r.stderr.decode().splitlines() if " simulated in " in line)
    # 75,000 instructions at 150 MHz are 500 us; ticks 4100-4299 call lab()
    assert re.search(r"; lab\(\) x200: mean [\d.]+ us, max [\d.]+ us \(tick \d+\); 0 over the budget of "
                     r"500 us", summary), summary


def test_nan_torque_warns_and_applies_nothing_on_that_joint():
    run = simulate(FAULTY / "nan_torque.c", "hands_off", duration_s=5.2, log=True)
    assert run.ok
    st = run.stats
    assert (st.nan_first_tick, st.nan_first_joint) == (5099, 2)
    log = run.log
    rows = log["tick"][:, 0] >= 5099
    assert np.all(np.isnan(log["tau_lab"][rows, 1]))
    assert np.all(log["tau_applied"][rows, 1] == 0.0)


def test_nan_torque_cli_warning_and_strict(tmp_path):
    r, _ = sim("nan_torque.c", tmp_path)
    assert r.returncode == 0
    assert ("crslab sim: warning: nan_torque.c returned a NaN or Inf in tau2 at tick 5099 (t = 5.099 s); "
            "no torque was applied on that joint for that tick") in r.stderr.decode()
    r, transcript = sim("nan_torque.c", tmp_path, "--strict")
    assert r.returncode == 5
    assert "tau2 at tick 5099" in last_line(r) and "--strict" in last_line(r)
    assert transcript == b"count 1 theta1 0.00\n\rcount 501 theta1 0.00\n\r"  # the run stopped at 5.099 s


def test_template_off_by_one_under_sanitize(tmp_path):
    r, transcript = sim("off_by_one_template.c", tmp_path, "--sanitize", "--duration", "10", timeout=240)
    assert r.returncode == 3, r.stderr.decode()[-2000:]
    line = last_line(r)
    assert line.startswith("crslab sim: off_by_one_template.c: AddressSanitizer: global-buffer-overflow "
                           "(WRITE of size 4) at off_by_one_template.c:24 in lab()")
    assert line.endswith("at tick 9100 (t = 9.100 s)")
    assert transcript.count(b"\n\r") == 10  # prints at calls 0, 500, ..., 4500 came through
    # without --sanitize the write lands in the next global and the run "works", as on the DSP
    r, _ = sim("off_by_one_template.c", tmp_path, "--duration", "10")
    assert r.returncode == 0


def test_flood_is_cut_off_with_bounded_output(tmp_path):
    # the serial line sends 11.52 characters per ms whatever the lab prints: 20 kB take 1.74 s
    r, transcript = sim("flood.c", tmp_path, "--max-output-mb", "0.02")
    assert r.returncode == 6
    assert "flood.c printed more than 0.02 MB; the run was cut off at tick" in last_line(r)
    assert len(transcript) == 20_000
    assert "characters did not fit the board's 2048-byte transmit ring" in r.stderr.decode()
    assert no_process_left(tmp_path / "flood.c")


def test_a_burst_far_beyond_the_transmit_ring_loses_what_does_not_fit_as_on_the_board(tmp_path):
    # 5000 lines of 1024 bytes at tick 0: Gen A's 2048-byte transmit ring takes the first two, the
    # FIFO and the shift register make room for 17 more characters; the rest never leaves the board
    kept = 2 * 1024 + 17
    run = simulate(FAULTY / "burst_in_one_tick.c", "hands_off", duration_s=0.35, startup_delay=False)
    assert run.ok and run.stats.tx_dropped == 5000 * 1024 - kept and run.stats.tx_first_drop_tick == 0
    assert run.stats.serial_dropped == 0  # crslab itself kept everything that left the board
    row = "".join(chr(ord("a") + i % 26) for i in range(1022))
    assert run.lines() == [row, row, row[:17] + "after 100", "after 200", "after 300"]
    # at 11.52 characters per ms the 2065 take 179.3 ms: the print of tick 100 waits its turn and
    # its first character leaves during tick 179
    assert [t for t, _ in run.calls] == [0, 0, 0, 100, 200, 300]
    assert run.sent[0] == (0, row[:11].encode())
    sent_by = np.cumsum([len(d) for _, d in run.sent])
    assert run.sent[int(np.searchsorted(sent_by, kept + 1))][0] == 179
    r, transcript = sim("burst_in_one_tick.c", tmp_path, "--no-startup-delay", "--duration", "0.35",
                        "--scenario", "hands_off", "--json")
    assert r.returncode == 0 and transcript == run.transcript
    info = json.loads(r.stderr.decode().strip().splitlines()[-1])
    assert info["tx_ring_dropped"] == 5000 * 1024 - kept and info["serial_dropped"] == 0


def test_isolation_does_not_change_the_transcript():
    config = make_config()
    isolated = simulate(duration_s=12.0).transcript
    assert isolated == run_in_process(config, 12_000)
    assert len(isolated) > 500
    # the in-process run used a private copy of the lab: a worker forked now starts afresh
    assert simulate(duration_s=12.0).transcript == isolated


def test_signed_overflow_under_sanitize(tmp_path):
    r, _ = sim("int_overflow.c", tmp_path, "--sanitize", timeout=240)
    assert r.returncode == 3
    assert last_line(r).startswith("crslab sim: int_overflow.c: UBSan: signed integer overflow: ")
    # 483 calls fit below 2**31 - 1; the 484th call (tick 4100 + 483) overflows
    calls_that_fit = (2**31 - 1 - 2147000000) // 1000
    tick = 4100 + calls_that_fit
    assert last_line(r).endswith(f"at int_overflow.c:20 in lab() at tick {tick} (t = {tick / 1000:.3f} s)")


def test_over_budget_calls_are_counted_in_instructions_the_same_on_every_machine(tmp_path):
    # 100 000 rounds of a float multiply-add: with the optimisation off, as on the board, each round
    # loads and stores its counter and the global, about 26 instructions
    r, _ = sim("busy_lab.c", tmp_path, "--duration", "4.110", "--json")
    assert r.returncode == 0, r.stderr.decode()
    info = json.loads(r.stderr.decode().strip().splitlines()[-1])
    assert info["lab_cost_unit"] == "instructions" and info["budget"] == 75_000
    assert info["lab_calls"] == 10 and info["over_budget"] == 10
    assert info["over_budget_ticks"] == list(range(4100, 4108))
    assert 1_500_000 < info["lab_cost_mean"] < 4_000_000
    again = json.loads(sim("busy_lab.c", tmp_path, "--duration", "4.110", "--json")[0].stderr.decode()
                       .strip().splitlines()[-1])
    assert (again["lab_cost_mean"], again["lab_cost_max"]) == (info["lab_cost_mean"], info["lab_cost_max"])
    r, _ = sim("busy_lab.c", tmp_path, "--duration", "4.110", "--json", "--budget", "10000000")
    assert json.loads(r.stderr.decode().strip().splitlines()[-1])["over_budget"] == 0


def test_a_native_lab_is_counted_in_cpu_time_and_cpu_limit_stops_the_lab(tmp_path):
    r, _ = sim("slow_lab.c", tmp_path, "--duration", "4.110", "--json", "--native")
    assert r.returncode == 0
    info = json.loads(r.stderr.decode().strip().splitlines()[-1])
    assert info["lab_cost_unit"] == "us" and info["budget"] == 500.0
    assert info["lab_calls"] == 10 and info["over_budget"] == 10
    assert info["over_budget_ticks"] == list(range(4100, 4108))
    assert info["lab_cost_mean"] > 2500
    r, _ = sim("slow_lab.c", tmp_path, "--duration", "8", "--cpu-limit", "1", "--native")
    assert r.returncode == 3
    assert "slow_lab.c used up its CPU-time limit (1 s) in lab() at tick" in last_line(r)
    assert no_process_left(tmp_path / "slow_lab.c")


def test_a_leaking_lab_gets_the_boards_memory_and_no_more(tmp_path):
    # the firmware's memory is fixed: malloc(64 MB) returns NULL, and memset through it runs off the end
    r, _ = sim("memory_hog.c", tmp_path)
    assert r.returncode == 3
    assert last_line(r) == ("crslab sim: memory_hog.c read or wrote outside its memory (a wild pointer or an "
                            f"index far out of an array) at memory_hog.c:25 {AT_5123}")


def test_memory_limit_stops_a_leaking_native_lab(tmp_path):
    r, transcript = sim("memory_hog.c", tmp_path, "--mem-limit-mb", "600", "--native")
    assert r.returncode == 3
    assert last_line(r).startswith("crslab sim: memory_hog.c crashed (SIG")
    assert " in lab() at tick " in last_line(r) and last_line(r).endswith("its memory limit was 600 MB")
    assert no_process_left(tmp_path / "memory_hog.c")


@pytest.mark.parametrize("stuck, leak_kb, status, ending", [
    # Every call returns, spinning 30 ms (a chunk of 300 ticks may use 0.3 s of CPU and its 0.5 s
    # deadline, 0.8 s, where it would use 9 s). 32 MB a call, some 1 GB a second of its CPU: past its
    # CPU allowance it is watched on while it grows, and its 4096 MB limit ends it, some 100 calls in
    (False, 32768, 3, "crashed (SIGSEGV) in lab() at tick "),
    # 0.5 MB a call, some 17 MB a second of its CPU (at most 30 MB by the first look past 0.8 s, the
    # looks a second of the wall clock apart), under the 64 MB that lets it go on: stuck
    (False, 512, 4, "hung: lab() did not return within 0.5 s at tick "),
    # The first call never returns, leaking 64 MB each 100 ms of its CPU, some 320 MB by each look past
    # its 0.5 s deadline: it is filling its memory, watched on until its 1024 MB limit ends it
    (True, 65536, 3, "crashed (SIGSEGV) in lab() at tick 0"),
    # 8 MB each 100 ms, some 40 MB by the first look past the deadline, under 64 MB: stuck
    (True, 8192, 4, "hung: lab() did not return within 0.5 s at tick 0"),
])
def test_a_native_lab_past_its_limits_is_hung_unless_it_fills_its_memory(stuck, leak_kb, status, ending,
                                                                         tmp_path):
    """A native lab's chunk may use 1 ms of CPU a tick and a deadline more (it could hide a stuck
    lab() by writing the board's phase), and one call its deadline; a leak's page faults are CPU and
    wall time too, so a leaking lab on a machine whose page faults are slow ran past both and was
    called hung at random, where its memory limit ends it."""
    memory_mb = 1024 if stuck else 4096
    defines = {"LEAK_KB": f"{leak_kb}L"} | ({"SPIN_PER_S": 10, "STUCK_FROM": 1} if stuck else {})
    r, _ = sim("slow_leak.c", tmp_path, "--native", "--no-startup-delay", "--duration", "0.3",
               "--mem-limit-mb", str(memory_mb), "--deadline", "0.5", defines=defines)
    assert r.returncode == status and f"slow_leak.c {ending}" in last_line(r), last_line(r)
    assert last_line(r).endswith(f"its memory limit was {memory_mb} MB") == (status == 3)
    assert no_process_left(tmp_path / "slow_leak.c")


@pytest.mark.parametrize("limit", ["deadline", "cpu"])
def test_a_worker_that_dies_as_its_limits_are_looked_at_is_not_called_hung(limit, monkeypatch):
    """A leaking lab's worker that died at its memory limit just as the watcher read its memory (a
    dying process's reads 0 before it is gone: not grown) was called hung, at random, under load;
    its death is what the run reports. Here the worker is killed as the watcher finds it not
    growing, and its memory then reads 0, as a dying one's does: past its one call's
    deadline, or past its chunk's CPU allowance (at real time, 20-tick chunks: 0.52 s of CPU; its
    call's own time not looked at, as a lab that overwrites the board's phase hides it)."""
    from crslab.run import worker_process
    from crslab.run.status import RunStatus

    workers: list[worker_process.WorkerProcess] = []
    opened = worker_process.WorkerProcess.__init__

    def kept(self: worker_process.WorkerProcess, *args: object, **kwargs: object) -> None:
        opened(self, *args, **kwargs)
        workers.append(self)

    read_memory = worker_process.WorkerProcess._vm_mb
    dying: list[bool] = []

    def dies_as_looked_at(grown_mb: float, memory_mb: int | None) -> bool:
        for worker in workers:  # killed, not waited for: it is dying as the watcher decides
            os.kill(worker.pid, 9)
        dying.append(True)
        return False

    def torn_down(worker: worker_process.WorkerProcess) -> float:
        return 0.0 if dying else read_memory(worker)  # a dying process's memory is freed first

    monkeypatch.setattr(worker_process.WorkerProcess, "__init__", kept)
    monkeypatch.setattr(worker_process, "still_growing", dies_as_looked_at)
    monkeypatch.setattr(worker_process.WorkerProcess, "_vm_mb", torn_down)
    if limit == "cpu":
        monkeypatch.setattr(worker_process.WorkerProcess, "_call_s", lambda worker, seen_at, wait_s: 0.0)
    # no memory limit: a worker forked from this test's process starts with its address space
    r = simulate(FAULTY / "hang_in_lab.c", duration_s=6.0, native=True, deadline_s=0.5,
                 speed=1.0 if limit == "cpu" else None)
    assert r.status == RunStatus.CRASHED and r.end_tick == 5123, (r.status, r.message)


@pytest.mark.parametrize("spin_s, sleep_s, status", [
    (0.4, 0.0, 0),  # 0.4 s of its own CPU, some 1.2 s of the wall clock beside two others: not hung
    (0.0, 1.5, 4),  # asleep 1.5 s, waiting on nothing: hung at its 1 s deadline
])
def test_a_native_call_is_timed_without_the_cores_others_took(spin_s, sleep_s, status, tmp_path):
    """A native lab's call is hung for the time it takes itself, not for the time its worker
    waited for a core: on one core with two busy programs its first call, 0.4 s of CPU, takes some
    1.2 s of the wall clock and is not hung at a 1 s deadline (a TA's grade beside its own jobs);
    a call that sleeps past the deadline still is."""
    core = min(os.sched_getaffinity(0))

    def one_core() -> None:
        os.sched_setaffinity(0, {core})

    hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"], preexec_fn=one_core)
            for _ in range(2)]
    try:
        r, _ = sim("slow_first_call.c", tmp_path, "--native", "--no-startup-delay", "--duration", "0.1",
                   "--deadline", "1", defines={"SPIN_FIRST_S": spin_s, "SLEEP_FIRST_S": sleep_s},
                   preexec_fn=one_core)
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()
    assert r.returncode == status, last_line(r)
    if status == 4:
        assert "slow_first_call.c hung: lab() did not return within 1 s at tick 0" in last_line(r)
    assert no_process_left(tmp_path / "slow_first_call.c")


def test_isolation_does_not_change_a_native_transcript():
    """The same with the lab built natively (the benchmarks' recording): the in-process run loads a
    sealed private copy of the lab's shared object (the board loads nothing this user did not seal)."""
    config = make_config(native=True)
    assert run_in_process(config, 12_000) == simulate(duration_s=12.0, native=True).transcript
