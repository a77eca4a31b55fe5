"""The crslab side of a run: starts the worker, paces it, reads what the board printed, and
turns a worker that crashes, exits or hangs into one line of diagnosis.

Time: tick k is at t = k ms (tick 0 is t = 0). Chunks of ticks are requested from the worker;
where chunks begin and end never changes what the lab sees, so the transcript is the same at
any speed. Serial bytes come with the tick during which they left the board (the board's serial
line sends 11.52 characters per ms); what is still on its way out when a run ends is handed on
last, marked with the tick the run ended at.
"""

from __future__ import annotations

import faulthandler
import multiprocessing as mp
import os
import resource
import signal
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from multiprocessing.reduction import DupFd
from pathlib import Path

import numpy as np

from crslab import os_support
from crslab.scenario.expect_events import ExpectOutcome, Judge, Observation
from crslab.sim import termination
from crslab.sim.board_ffi import board_constants, board_ffi, shared_size
from crslab.sim.config import SimConfig
from crslab.sim.debug_setup import DebugSetup
from crslab.sim.firmware_trap import diagnose
from crslab.sim.host_ports import PortExchange, exchange, port_index
from crslab.sim.running import LiveControl, PacedControl, RunDebugger
from crslab.sim.sanitizer import asan_runtime, summarize_sanitizer_report
from crslab.sim.status import RunResult, RunStatus
from crslab.sim.wasm_runtime import INTERRUPT_SIGNAL
from crslab.sim.worker_reply import UnreadableReply, receive
from crslab.sinks.sink import Sink
from crslab.untrusted_text import for_terminal

DEFAULT_DEADLINE_S = 2.0
INTERRUPT_GRACE_S = 2.0
"""How long a WebAssembly worker has to answer once its firmware's call was interrupted."""
CPU_S_PER_TICK = 1e-3
"""The CPU time a chunk may use per tick before the worker counts as hung whatever it reports
(a native lab could hide that it is stuck in lab()): a millisecond, a slow lab's whole tick."""
READY_TIMEOUT_S = 60.0
SANITIZER_REPORT_ENV = "CRSLAB_SANITIZER_REPORT"
ABORT_ON_ERROR = ":abort_on_error=1"
REALTIME_SLICE_TICKS = 20
FAST_SLICE_TICKS = 20_000
DEBUG_SLICE_TICKS = 20
"""Chunks of a debugged run: what was printed up to 19 ticks before a stop in the debugger is on
the terminal (a chunk's serial bytes are taken when it ends)."""
MotorBoardReport = Callable[[int, int, bool], None]
"""``(tick, joint, off)``: the motor board cut every output (off True; joint 1..3 over the limit,
0 no command) or brought them back (off False)."""
ExpectationReport = Callable[[ExpectOutcome], None]
"""An expectation of the scenario was judged (met or failed)."""


def phase_where(phase: int) -> str:
    """Where the worker was, for a diagnosis, from the phase it wrote (``CRS_PHASE_*``).

    >>> phase_where(board_constants().CRS_PHASE_PRINTING)
    'in printing()'
    """
    c = board_constants()
    return {c.CRS_PHASE_IDLE: "between ticks", c.CRS_PHASE_LAB: "in lab()",
            c.CRS_PHASE_PRINTING: "in printing()", c.CRS_PHASE_PHYSICS: "in the physics step",
            c.CRS_PHASE_LOADING: "in a constructor or static initializer"}.get(phase, "")


class SimError(Exception):
    """The run could not start (the worker failed before the first tick); ``status`` says how
    (crashed, or forbidden when a constructor tried what the sandbox refuses)."""

    def __init__(self, message: str, status: RunStatus = RunStatus.CRASHED) -> None:
        super().__init__(message)
        self.status = status


@dataclass(frozen=True)
class Limits:
    """What one run may use: worker memory and CPU time (None: no limit), printed bytes."""

    memory_mb: int | None = None
    cpu_s: float | None = None
    output_bytes: int = 16 * 1024 * 1024


NO_LIMITS = Limits()


def _child(conn: Connection, config: SimConfig, shared: DupFd, limits: Limits = NO_LIMITS,
           debug: DebugSetup | None = None, console: DupFd | None = None) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the crslab process's to handle
    if config.build.native:  # a crash is diagnosed by the crslab process, not dumped here (a WebAssembly
        faulthandler.disable()  # firmware's faults are wasmtime's: its handlers stay as they are)
    os_support.die_with_parent()  # whatever kills the crslab process
    if debug is not None:  # Ctrl-C on the terminal is the debugger's: it interrupts the lab itself
        os.setpgid(0, 0)
    if console is not None:  # a native lab's printf: counted by the crslab process, never shown
        fd = console.detach()
        os.dup2(fd, 1)
        os.dup2(fd, 2)
        os.close(fd)
    report = os.environ.pop(SANITIZER_REPORT_ENV, None)
    if report:  # the sanitizers write to stderr: keep it for the crslab process to read
        fd = os.open(report, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        os.dup2(fd, 2)
        os.close(fd)
    if limits.memory_mb is not None:
        os_support.limit_memory(limits.memory_mb * 1024 * 1024)
    if limits.cpu_s is not None:
        cpu = int(limits.cpu_s) + 1
        resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 1))
    from crslab.sim.worker import serve

    serve(conn, config, shared.detach(), debug)
    os._exit(0)


class CtrlC:
    """Ctrl-C (SIGINT) during a run, in the main thread: raised as ``KeyboardInterrupt`` at once,
    except while a chunk's bytes are being handed to the sinks (:meth:`held`), where it waits
    until every sink has them, so stdout and the transcript never differ. Elsewhere (another
    thread, a handler of the caller's own) it leaves SIGINT alone."""

    def __init__(self) -> None:
        self.holding = False
        self.pending: int | bool = False
        """The signal held back (SIGINT, SIGTERM, SIGHUP) while a chunk's bytes were handed on."""
        self._old: object = None

    def __enter__(self) -> CtrlC:
        self._taken: dict[int, object] = {}  # SIGTERM and SIGHUP too, where crslab's command raises them
        if (threading.current_thread() is threading.main_thread()
                and signal.getsignal(signal.SIGINT) is signal.default_int_handler):
            self._old = signal.signal(signal.SIGINT, self._on_sigint)
            for signum in termination.SIGNALS:
                if signal.getsignal(signum) is termination.raise_terminated:
                    self._taken[signum] = signal.signal(signum, self._on_sigint)
        return self

    def __exit__(self, *exc: object) -> None:
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)
            self._old = None
        for signum, old in self._taken.items():
            signal.signal(signum, old)  # type: ignore[arg-type]
        self._taken = {}

    def _on_sigint(self, signum: int, frame: object) -> None:
        if self.holding:
            self.pending = self.pending or signum
            if signum != signal.SIGINT:
                termination.received = signum
        elif signum != signal.SIGINT:
            termination.raise_terminated(signum, frame)
        else:
            raise KeyboardInterrupt

    @contextmanager
    def held(self) -> Iterator[None]:
        """Hold a Ctrl-C back until the block is done, then raise it."""
        self.holding = True
        try:
            yield
        finally:
            self.holding = False
        if self.pending:
            signum, self.pending = self.pending, False
            if signum != signal.SIGINT:
                termination.raise_terminated(int(signum), None)
            raise KeyboardInterrupt


class Simulation:
    """A running lab: ``with Simulation(config) as sim: sim.run(end_tick, ...)``.

    ``debug`` prepares the worker for a debugger (``crslab debug``): the process it names may
    trace it. ``deadline_s`` None never calls the lab hung (a debugger holds it as long as it
    likes). ``on_started()`` is called once the worker process exists, while it loads the plant
    and the lab: what it starts overlaps the worker's start-up (threads may start then: the fork
    is done).
    """

    def __init__(self, config: SimConfig, *, deadline_s: float | None = DEFAULT_DEADLINE_S,
                 limits: Limits = NO_LIMITS, debug: DebugSetup | None = None,
                 on_started: Callable[[], None] | None = None) -> None:
        self.config = config
        self.deadline_s = deadline_s
        self.debug = debug
        self.limits = limits
        self.sanitizer_dir: str | None = None
        self._rss_limit_mb: int | None = None
        self.lab_name = config.build.source.name
        self.ffi = board_ffi()
        # the shared block is memory with no name in any file system: it goes when both processes do,
        # however they end (killed by a grader's time limit included)
        fd = os_support.anonymous_shared_file("crslab-shared", shared_size())
        import mmap

        self._shared_mm = mmap.mmap(fd, 0)
        self._shared_fd = fd
        self.shared = self.ffi.cast("crs_shared *", self.ffi.from_buffer(self._shared_mm))
        self.tick = 0
        self.stats: dict = {}
        self.serial_dropped = 0
        """Bytes that left the board but never reached the sinks: more in one chunk than the shared
        block holds (``CRS_SERIAL_CAPACITY`` bytes, ``CRS_MARK_CAPACITY`` ticks). The serial line's
        11.52 characters per ms keep a chunk far below that. In ``stats`` too."""
        self.motor_board_events: list[tuple[int, int, int]] = []
        """The motor board's cut-outs so far: ``(tick, joint, off)``. In ``stats`` too."""
        self.judge = Judge(config.scenario.events, config.scenario.source)
        """The scenario's expectations, judged as the worker's observations arrive."""
        self.symbols = 0
        sys.stdout.flush()
        sys.stderr.flush()
        if config.build.sanitized:
            # the sanitizer runtime must be loaded first: a fresh interpreter with it preloaded
            ctx = mp.get_context("spawn")
            self.sanitizer_dir = tempfile.mkdtemp(prefix="crslab-sanitize-")
            env = {
                os_support.PRELOAD_ENV: asan_runtime(config.build.compiler),
                # under a debugger a finding ends in abort(), where the debugger stops
                "ASAN_OPTIONS": "detect_leaks=0:halt_on_error=1" + (ABORT_ON_ERROR if debug else ""),
                "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1" + (ABORT_ON_ERROR if debug else ""),
                SANITIZER_REPORT_ENV: os.path.join(self.sanitizer_dir, "report.txt"),
            }
            # one thread, as the sandbox needs: no BLAS thread pool in the fresh interpreter
            env.update({k: "1" for k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")})
            # ASan reserves terabytes of address space: its memory is watched instead (resident)
            self._rss_limit_mb = limits.memory_mb
            limits = Limits(None, limits.cpu_s, limits.output_bytes)
        else:
            ctx = mp.get_context(os_support.WORKER_START_METHOD)
            env = {}
        # a native lab may write to its standard streams (printf, a flood, fake progress lines): a pipe
        # the crslab process drains, counts toward the output limit and never shows (a debugged one
        # keeps the terminal); a WebAssembly firmware has no descriptor at all (the board counts)
        self._console = -1
        self.console_bytes = 0
        console = None
        if config.build.native and debug is None:
            self._console, console_w = os.pipe()
            os.set_blocking(self._console, False)
            console = DupFd(console_w)
        saved = {k: os.environ.get(k) for k in env}
        os.environ.update(env)
        try:
            self._conn, child_conn = ctx.Pipe()
            args = (child_conn, config, DupFd(self._shared_fd), limits, debug, console)
            self.process = ctx.Process(target=_child, args=args, daemon=True)
            self.process.start()
        finally:
            if console is not None:
                os.close(console_w)
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
        child_conn.close()
        if on_started is not None:
            on_started()
        reply = self._expect(self._wait_reply(READY_TIMEOUT_S, during_setup=True),
                             ("ready", "failed", "trapped"), 2)
        if not isinstance(reply, RunResult) and reply[0] == "trapped" and isinstance(reply[1], dict):
            status, message = diagnose(reply[1], self.lab_name, deadline_s=self.deadline_s)
            reply = RunResult(status, 0, message)
        elif not isinstance(reply, RunResult) and (reply[0] != "ready" or not isinstance(reply[1], int)):
            reply = RunResult(RunStatus.CRASHED, 0, f"{self.lab_name}: {reply[1]}")
        if isinstance(reply, RunResult):
            self.close()
            raise SimError(reply.message, reply.status)
        self.symbols = reply[1]

    @property
    def worker_pid(self) -> int:
        """The process id of the worker (the process that runs the lab)."""
        pid = self.process.pid
        assert pid is not None
        return pid

    @property
    def defines_lab(self) -> bool:
        """Whether the lab file defines ``lab()`` (the board would not link without one)."""
        return bool(self.symbols & board_constants().CRS_LAB_HAS_LAB)

    # -- lifecycle ---------------------------------------------------------------------------
    def __enter__(self) -> Simulation:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Stop the worker (it leaves no process behind) and free the shared block."""
        if self.process.is_alive():
            try:
                self._conn.send(("stop",))
                if self._conn.poll(2.0):
                    reply = receive(self._conn)
                    if isinstance(reply, tuple) and len(reply) == 3 and isinstance(reply[1], dict):
                        self.stats = reply[1] or self.stats
            except (OSError, EOFError, BrokenPipeError, UnreadableReply):
                pass
            self.process.join(2.0)
            if self.process.is_alive():
                self.process.kill()
        self.process.join()
        self._conn.close()
        if self._shared_fd >= 0:
            os.close(self._shared_fd)
            self._shared_fd = -1
        if self._console >= 0:
            os.close(self._console)
            self._console = -1
        if self.sanitizer_dir:
            for p in Path(self.sanitizer_dir).glob("*"):
                p.unlink()
            os.rmdir(self.sanitizer_dir)

    # -- serial ------------------------------------------------------------------------------
    def _drain_serial(self, take: Callable[[int, bytes], None], sink: Sink) -> int:
        """Hand the print marks since the last drain to ``sink.on_print(tick, chars)`` and the
        bytes that left the board to ``take(tick, bytes)``, one call per tick that sent any;
        returns how many bytes could not be kept since then (more in one chunk than the shared
        block holds), which :attr:`serial_dropped` counts too.

        The block is the lab's to scribble on: lengths and offsets are clamped to the block, so
        nothing but the block is ever read."""
        sh = self.shared
        for i in range(min(int(sh.print_count), len(sh.print_tick))):
            sink.on_print(int(sh.print_tick[i]), int(sh.print_chars[i]))
        sh.print_count = 0
        dropped = max(0, int(sh.serial_dropped))
        sh.serial_dropped = 0
        self.serial_dropped += dropped
        n_bytes = min(int(sh.serial_len), len(sh.serial))
        n_marks = min(int(sh.mark_count), len(sh.mark_offset))
        if n_bytes:
            raw = bytes(self.ffi.buffer(sh.serial, n_bytes))
            offsets = [min(int(sh.mark_offset[i]), n_bytes) for i in range(n_marks)] + [n_bytes]
            for i in range(n_marks):
                take(int(sh.mark_tick[i]), raw[offsets[i]:max(offsets[i], offsets[i + 1])])
        sh.serial_len = 0
        sh.mark_count = 0
        return dropped

    def _drain_line(self, take: Callable[[int, bytes], None], tick: int) -> None:
        """Hand what is still on the board's serial line (queued, not yet sent) to ``take``, marked
        with ``tick``: called once the run has ended, so nothing the lab printed is lost."""
        line = self.shared.line
        size = self.ffi.sizeof(line.queue)
        n, first = min(int(line.len), size), int(line.first) % size  # a crashed lab may have scribbled
        if n:
            queue = bytes(self.ffi.buffer(line.queue, size))
            take(tick, (queue[first:] + queue[:first])[:n])
        line.len = 0

    def _overflow(self) -> tuple[int, str]:
        """The tick and the diagnosis of a serial_printf that overflowed the board's buffer."""
        st = self.stats
        tick = int(st.get("overflow_tick", self.tick))
        where = phase_where(int(st.get("overflow_phase", 0)))
        buffer = self.config.build.printf_buffer_chars
        return tick, (f"{self.lab_name}: a serial_printf {where} at tick {tick} (t = {tick / 1000:.3f} s) "
                      f"formatted {st.get('overflow_chars', 0)} characters; the board's {buffer}-byte "
                      f"serial_printf buffer holds {buffer - 1} and a terminating NUL, so this line "
                      "overflows it and corrupts the board's memory")

    # -- watched variables -------------------------------------------------------------------
    def _ask(self, msg: tuple) -> object:
        self._conn.send(msg)
        reply = self._expect(self._wait_reply(None), ("value", "error"), 2)
        if isinstance(reply, RunResult):
            raise SimError(reply.message)
        if reply[0] == "error":
            raise KeyError(reply[1])
        return reply[1]

    def get(self, name: str) -> float | list[float]:
        """Read a watched variable of the running lab (between ticks)."""
        value = self._ask(("get", name))
        assert isinstance(value, float | list)
        return value

    def set(self, name: str, value: float, index: int | None = None) -> None:
        """Write a watched variable (or one array element) of the running lab, between ticks."""
        self._ask(("set", name, index, float(value)))

    def exchange(self, port: str, incoming: bytes) -> PortExchange:
        """Between chunks: what left the board on host port ``port`` (``SerialB``, ``SerialC``)
        since the last call; ``incoming`` goes to its receiver from the next tick on (as much as
        its inbox takes now: :attr:`PortExchange.taken`)."""
        return exchange(self.ffi, self.shared.host_ports[port_index(port)], incoming)

    def push(self, body_forces: np.ndarray) -> None:
        """Apply a force and torque to each body (MuJoCo ``xfrc_applied``, world frame, N and N.m)
        from the next tick on, until the next push: MuJoCo's viewer passes the mouse's drag."""
        self._ask(("push", np.asarray(body_forces, dtype=float).tolist()))

    def debug_break(self) -> None:
        """Have the worker call ``crs_debug_break``: the debugger attached to it stops there and
        arms its breakpoint on ``lab()``, so it stops in the next ``lab()`` call (this tick's)."""
        self._ask(("break",))

    # -- running -----------------------------------------------------------------------------
    def _refusal(self, code: int | None) -> RunResult | None:
        """The run stopped by the sandbox: what the lab tried, where and when (None if not)."""
        record = self.shared.refusal
        if not record.refused and code != -signal.SIGSYS:
            return None
        from crslab.sandbox.refusal import tried

        phase = int(record.phase) if record.refused else int(self.shared.phase)
        tick = int(record.tick) if record.refused else int(self.shared.tick)
        what = for_terminal(tried(record, self.ffi, parent_pid=os.getpid())) if record.refused else \
            "make a system call the sandbox refuses"
        at = "before the first tick" if phase == board_constants().CRS_PHASE_LOADING else \
            f"at tick {tick} (t = {tick / 1000:.3f} s)"
        return RunResult(RunStatus.FORBIDDEN, tick, f"{self.lab_name} was stopped by the sandbox: it tried "
                         f"to {what} {phase_where(phase)} {at}", self.stats)

    def _expect(self, reply: object, kinds: tuple[str, ...], size: int) -> tuple | RunResult:
        """``reply`` if it is a tuple of ``size`` whose first item is one of ``kinds``."""
        if isinstance(reply, RunResult) or (isinstance(reply, tuple) and len(reply) == size
                                            and reply[0] in kinds):
            return reply
        return self._tampered(f"it sent {type(reply).__name__} where {kinds[0]} was due")

    def _tampered(self, what: str) -> RunResult:
        """The lab wrote into the pipe to crslab (it is unpickled by nobody): the run ends. The
        worker may have run on a little since, so the tick is an upper bound."""
        self.process.kill()
        self.process.join()
        tick = int(self.shared.tick)
        return RunResult(RunStatus.FORBIDDEN, tick, f"{self.lab_name} was stopped by the sandbox: it tried "
                         f"to write into crslab's pipe ({what}) by tick {tick} (t = {tick / 1000:.3f} s)",
                         self.stats)

    def _diagnose_death(self) -> RunResult:
        self.process.join(1.0)
        code = self.process.exitcode
        tick = int(self.shared.tick)
        where = phase_where(int(self.shared.phase))
        at = f"at tick {tick} (t = {tick / 1000:.3f} s)"
        report = self._sanitizer_report()
        if report is not None:  # first: a sanitizer's own report may touch what the sandbox refuses
            where = "" if report.endswith("()") else f" {where}"
            return RunResult(RunStatus.CRASHED, tick, f"{self.lab_name}: {report}{where} {at}", self.stats)
        refused = self._refusal(code)
        if refused is not None:
            return refused
        if code == -signal.SIGFPE and self.debug is not None and self.debug.trap_fp:
            return RunResult(RunStatus.CRASHED, tick, f"{self.lab_name} raised a floating-point exception "
                             f"(SIGFPE) {where} {at}: an operation that made a NaN or an infinity (with "
                             "--strict and --debug-on-crash), or an integer division by zero", self.stats)
        if code == -signal.SIGKILL and self.debug is not None:
            return RunResult(RunStatus.CRASHED, tick, f"{self.lab_name}'s process was killed (SIGKILL) "
                             f"{where} {at}: by the debugger's kill, or by the system", self.stats)
        if code == -signal.SIGXCPU:
            return RunResult(RunStatus.CRASHED, tick, f"{self.lab_name} used up its CPU-time limit "
                             f"({self.limits.cpu_s:g} s) {where} {at}", self.stats)
        if code is not None and code < 0:
            name = signal.Signals(-code).name
            hint = f"; its memory limit was {self.limits.memory_mb} MB" if self.limits.memory_mb else ""
            return RunResult(RunStatus.CRASHED, tick, f"{self.lab_name} crashed ({name}) {where} {at}{hint}",
                             self.stats)
        return RunResult(RunStatus.EXITED, tick, f"{self.lab_name} called exit({code}) {where} {at}",
                         self.stats)

    def _sanitizer_report(self) -> str | None:
        """The first sanitizer finding, as one phrase naming the user's file and line."""
        if not self.sanitizer_dir:
            return None
        for path in sorted(Path(self.sanitizer_dir).glob("report.txt")):
            text = path.read_text(errors="replace")
            found = summarize_sanitizer_report(text, self.config.build.source.name)
            if found:
                return found
        return None

    def _worker_cpu_s(self) -> float | None:
        """The worker's CPU time so far (the kernel's count, which nothing in the worker can
        change), or None when it cannot be read."""
        try:
            fields = Path(f"/proc/{self.worker_pid}/stat").read_text().rsplit(")", 1)[1].split()
            return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
        except (OSError, IndexError, ValueError):
            return None

    def _wait_reply(self, timeout_s: float | None, during_setup: bool = False,
                    cpu_allowance_s: float | None = None) -> tuple | RunResult:
        """The worker's next reply, or how the run ended meanwhile: the worker died, or a lab()
        or printing() call ran past the deadline (a WebAssembly firmware is interrupted and the
        worker answers; a native worker is killed), or the worker used more than
        ``cpu_allowance_s`` of CPU time on this request (a native lab that hides where it is)."""
        c = board_constants()
        start = time.monotonic()
        cpu0 = self._worker_cpu_s() if cpu_allowance_s is not None else None
        interrupted_at: float | None = None
        polls = 0
        while True:
            try:
                ready = wait([self._conn, *([self._console] if self._console >= 0 else [])], 0.05)
                if self._console in ready and self._drain_console():
                    return self._cut_off(int(self.shared.tick))
                if self._conn in ready and self._conn.poll(0):
                    return receive(self._conn)
            except (EOFError, ConnectionResetError):
                pass
            except UnreadableReply as exc:
                return self._tampered(str(exc))
            if not self.process.is_alive():
                if during_setup:
                    self.process.join(1.0)
                    code = self.process.exitcode
                    refused = self._refusal(code)
                    if refused is not None:
                        return refused
                    how = signal.Signals(-code).name if code and code < 0 else f"exit status {code}"
                    return RunResult(RunStatus.CRASHED, 0, f"{self.lab_name} could not be loaded ({how})")
                return self._diagnose_death()
            phase = int(self.shared.phase)
            if self.deadline_s is not None and phase in (c.CRS_PHASE_LAB, c.CRS_PHASE_PRINTING):
                busy_s = (time.monotonic_ns() - int(self.shared.phase_start_ns)) / 1e9
                if busy_s > self.deadline_s:
                    if not self.config.build.native and interrupted_at is None:
                        # the firmware's call traps at its next loop or call; the worker answers
                        os.kill(self.worker_pid, INTERRUPT_SIGNAL)
                        interrupted_at = time.monotonic()
                    elif interrupted_at is None or time.monotonic() - interrupted_at > INTERRUPT_GRACE_S:
                        return self._hung(phase)
            if self._rss_limit_mb is not None and self._worker_rss_mb() > self._rss_limit_mb:
                return self._over_memory()
            polls += 1
            if cpu0 is not None and polls % 20 == 0:
                cpu = self._worker_cpu_s()
                if cpu is not None and cpu - cpu0 > cpu_allowance_s:  # type: ignore[operator]
                    return self._hung(c.CRS_PHASE_LAB)
            if timeout_s is not None and time.monotonic() - start > timeout_s:
                self.process.kill()
                return RunResult(RunStatus.CRASHED, int(self.shared.tick),
                                 f"{self.lab_name}: the worker stopped answering")

    def _worker_rss_mb(self) -> float:
        """The worker's resident memory (the kernel's count), MB; 0 when it cannot be read."""
        try:
            pages = int(Path(f"/proc/{self.worker_pid}/statm").read_text().split()[1])
        except (OSError, IndexError, ValueError):
            return 0.0
        return pages * os.sysconf("SC_PAGE_SIZE") / 2**20

    def _over_memory(self) -> RunResult:
        """The worker is killed: a sanitized lab used more memory than its limit."""
        tick = int(self.shared.tick)
        where = phase_where(int(self.shared.phase))
        self.process.kill()
        self.process.join()
        return RunResult(RunStatus.CRASHED, tick, f"{self.lab_name} used more than its memory limit "
                         f"({self.limits.memory_mb} MB) {where} at tick {tick} (t = {tick / 1000:.3f} s)",
                         self.stats)

    def _drain_console(self) -> bool:
        """Read (and drop) what a native lab wrote to its standard streams; True once it is more
        than the output limit."""
        while True:
            try:
                data = os.read(self._console, 1 << 20)
            except BlockingIOError:
                break
            if not data:
                break
            self.console_bytes += len(data)
        return self.console_bytes > self.limits.output_bytes

    def _cut_off(self, tick: int) -> RunResult:
        """The worker is killed: the lab printed more than the output limit."""
        self.process.kill()
        self.process.join()
        return RunResult(RunStatus.OUTPUT_LIMIT, tick, f"{self.lab_name} printed more than "
                         f"{self.limits.output_bytes / 1e6:g} MB; the run was cut off at tick {tick} "
                         f"(t = {tick / 1000:.3f} s)", self.stats)

    def _hung(self, phase: int) -> RunResult:
        """The worker is killed: its lab() or printing() did not return."""
        tick = int(self.shared.tick)
        self.process.kill()
        self.process.join()
        func = "printing()" if phase == board_constants().CRS_PHASE_PRINTING else "lab()"
        within = f" within {self.deadline_s:g} s" if self.deadline_s is not None else ""
        return RunResult(RunStatus.HUNG, tick, f"{self.lab_name} hung: {func} did not return{within} at tick "
                         f"{tick} (t = {tick / 1000:.3f} s)", self.stats)

    def run(
        self,
        end_tick: int,
        sink: Sink | None = None,
        *,
        speed: float | None = None,
        controls: Sequence[LiveControl] = (),
        on_behind: Callable[[float], None] | None = None,
        on_motor_board: MotorBoardReport | None = None,
        on_expectation: ExpectationReport | None = None,
        debugger: RunDebugger | None = None,
    ) -> RunResult:
        """Run to ``end_tick``, handing what the board prints and the scope rows to ``sink``;
        ``speed`` None is as fast as possible, else x real time.

        After every chunk of ticks, once ``sink`` took its serial bytes and scope rows and was
        flushed, each of ``controls`` is served: the worker is idle then, so they may call
        :meth:`get`, :meth:`set`, :meth:`push` and :meth:`exchange` (live variables, the viewer's
        mouse, the host ports); a :class:`~crslab.sim.running.PacedControl` among them (the serial
        bridge while a host program is attached) shortens the chunks to what it asks, and is
        served again right before the next chunk when the run waited for the wall clock.
        ``on_behind(rate)`` is called once when the machine cannot keep up with ``speed``;
        ``on_motor_board(tick, joint, off)`` whenever the motor board cuts every output or brings
        them back (the result's ``stats["motor_board_events"]`` lists them all);
        ``on_expectation(outcome)`` when an expectation of the scenario was judged, before the
        sinks get the chunk it was in. A run that reaches its end with a failed expectation ends
        ``unmet``; the result's ``expectations`` say how each went.

        With a ``debugger`` (``crslab debug``) chunks are short (:data:`DEBUG_SLICE_TICKS`) and
        end at the tick it names, where it is called; time spent stopped in the debugger is not
        made up for: pacing starts again from where the lab resumed.
        """
        sink = sink if sink is not None else Sink()
        wall0, tick0 = time.monotonic(), self.tick
        pace_wall, pace_tick = wall0, tick0  # where pacing counts from
        warned = False
        printed = 0
        console_seen = 0
        cap = self.limits.output_bytes

        def counted(tick: int, data: bytes) -> None:
            nonlocal printed
            keep = data[: max(0, cap - printed)]
            printed += len(data)
            if keep:
                sink.on_serial(tick, keep)

        def ended(status: RunStatus, tick: int, message: str = "") -> RunResult:
            self._drain_serial(counted, sink)
            self._drain_line(counted, tick)
            stats = {**self.stats, "serial_dropped": self.serial_dropped, "lab_symbols": self.symbols,
                     "motor_board_events": list(self.motor_board_events),
                     "console_bytes": max(int(self.stats.get("console_bytes", 0)), self.console_bytes)}
            expectations = self.judge.results()
            failed = sum(bool(e.failures) for e in expectations)
            if status is RunStatus.OK and failed:
                status = RunStatus.UNMET
                message = (f"{failed} of {len(expectations)} expectations of scenario "
                           f"{self.config.scenario.name} failed")
            return RunResult(status, tick, message, stats, lab_file=self.config.build.source,
                             wall_s=time.monotonic() - wall0, expectations=expectations)

        with CtrlC() as ctrl_c:
            try:
                while self.tick < end_tick:
                    step = FAST_SLICE_TICKS if speed is None else max(1, int(REALTIME_SLICE_TICKS * speed))
                    step = min([step] + [t for c in controls if isinstance(c, PacedControl)
                                         and (t := c.chunk_ticks(speed)) is not None])
                    target = min(end_tick, self.tick + step)
                    pause = debugger.pause_tick() if debugger is not None else None
                    if debugger is not None:
                        target = min(target, self.tick + DEBUG_SLICE_TICKS)
                        if pause is not None and pause > self.tick:
                            target = min(target, pause)
                    self._conn.send(("run", target))
                    # a chunk may use up to a millisecond of CPU per tick, and a deadline's worth more
                    allowance = (target - self.tick) * CPU_S_PER_TICK + (self.deadline_s or 0.0) \
                        if self.deadline_s is not None else None
                    reply = self._expect(self._wait_reply(None, cpu_allowance_s=allowance), ("ran",), 5)
                    if not isinstance(reply, RunResult) and not (isinstance(reply[2], int)
                                                                 and isinstance(reply[3], dict)):
                        reply = self._tampered("not the reply to a run request")
                    if isinstance(reply, RunResult):
                        ctrl_c.holding = True  # the run ends: a Ctrl-C now lets the last bytes out
                        return ended(reply.status, reply.end_tick, reply.message)
                    _, code, self.tick, self.stats, log = reply
                    if code == board_constants().CRS_RUN_TRAPPED:
                        ctrl_c.holding = True  # the run ends: a Ctrl-C now lets the last bytes out
                        trap = self.stats.get("trap")
                        status, message = diagnose(trap if isinstance(trap, dict) else {}, self.lab_name,
                                                   deadline_s=self.deadline_s)
                        return ended(status, self.tick, message)
                    for event in self.stats.pop("motor_board_events", []):
                        self.motor_board_events.append(tuple(event))
                        if on_motor_board is not None:
                            on_motor_board(event[0], event[1], bool(event[2]))
                    try:
                        judged = [self.judge.observed(observation(raw))
                                  for raw in self.stats.pop("observations", [])]
                    except (ValueError, TypeError, KeyError, IndexError) as exc:
                        ctrl_c.holding = True  # the run ends: a Ctrl-C now lets the last bytes out
                        bad = self._tampered(f"it sent an observation crslab cannot read: {exc}")
                        return ended(bad.status, bad.end_tick, bad.message)
                    for outcome in judged:
                        if outcome is not None and on_expectation is not None:
                            on_expectation(outcome)
                    with ctrl_c.held():  # every sink gets all of the chunk, or none of it
                        lost = self._drain_serial(counted, sink)
                        printed += lost  # what was lost counts toward the limit too
                        # printf: counted, never shown (the board's count, or what a native lab wrote)
                        console = max(int(self.stats.get("console_bytes", 0)), self.console_bytes)
                        printed += console - console_seen
                        console_seen = console
                        if printed <= cap:
                            if log is not None:
                                sink.on_log(log)
                            sink.flush()
                    if printed > cap:
                        ctrl_c.holding = True  # the run ends: a Ctrl-C now lets the last bytes out
                        return ended(RunStatus.OUTPUT_LIMIT, self.tick,
                                     f"{self.lab_name} printed more than {cap / 1e6:g} MB; the run was "
                                     f"cut off at tick {self.tick} (t = {self.tick / 1000:.3f} s)")
                    for control in controls:
                        control.serve(self)
                    if code == board_constants().CRS_RUN_NAN_STRICT:
                        ctrl_c.holding = True  # the run ends: a Ctrl-C now lets the last bytes out
                        t = self.stats.get("nan_first_tick", self.tick)
                        return ended(RunStatus.NAN, self.tick,
                                     f"{self.lab_name} returned a NaN or Inf in "
                                     f"tau{self.stats.get('nan_first_joint', 0)} at tick {t} "
                                     f"(t = {t / 1000:.3f} s) and --strict is on")
                    if code == board_constants().CRS_RUN_PRINTF_OVERFLOW:
                        ctrl_c.holding = True  # the run ends: a Ctrl-C now lets the last bytes out
                        return ended(RunStatus.CRASHED, *self._overflow())
                    broke = code == board_constants().CRS_RUN_BREAK
                    if debugger is not None and (broke or self.tick == pause):
                        debugger.paused(self, broke)
                    if speed is not None:
                        due = pace_wall + (self.tick - pace_tick) / 1000.0 / speed
                        lag = time.monotonic() - due
                        if lag < 0:
                            time.sleep(-lag)
                            for control in controls:  # what a host sent while we slept: this tick
                                if isinstance(control, PacedControl):
                                    control.serve(self)
                        elif lag > 0.5 and debugger is not None:  # the lab was held: pace from now on
                            pace_wall, pace_tick = time.monotonic(), self.tick
                        elif lag > 0.5 and not warned and on_behind is not None:
                            sim_s = (self.tick - tick0) / 1000.0
                            on_behind(sim_s / (time.monotonic() - wall0))
                            warned = True
            except KeyboardInterrupt as exc:
                ctrl_c.holding = True  # another Ctrl-C now waits for the last bytes too
                self.process.kill()
                self.process.join()
                tick = int(self.shared.tick)
                how = f"terminated ({exc.name})" if isinstance(exc, termination.Terminated) else "interrupted"
                return ended(RunStatus.INTERRUPTED, tick, f"{how} at t = {tick / 1000:.3f} s")
            ctrl_c.holding = True  # the run ends: a Ctrl-C now lets the last bytes out
            return ended(RunStatus.OK, self.tick)


def observation(raw: object) -> Observation:
    """An expectation's observation from the worker's reply, checked (the reply is the lab's to
    forge): raises ``ValueError``, ``TypeError`` or ``KeyError`` for anything else.

    >>> observation({"tick": 5, "motor_board": "none", "motor_board_off": 0, "motor_board_cutouts": 0,
    ...              "error": 1, "motor_rad": [0.0, 0.1, 0.2], "var": None}).error
    1
    >>> observation({"tick": 5})
    Traceback (most recent call last):
    ...
    KeyError: 'motor_rad'
    """
    if not isinstance(raw, dict):
        raise TypeError(f"{type(raw).__name__} is not an observation")

    def whole(key: str) -> int:
        value = raw[key]
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"{key} is not a whole number")
        return value

    angles = raw["motor_rad"]
    if not isinstance(angles, list) or len(angles) != 3 or not all(isinstance(v, float) for v in angles):
        raise TypeError("motor_rad is not three numbers")
    var = raw["var"]
    if var is not None and not isinstance(var, float):
        raise TypeError("var is not a number")
    board = raw["motor_board"]
    if not isinstance(board, str):
        raise TypeError("motor_board is not a name")
    return Observation(tick=whole("tick"), motor_board=board, motor_board_off=bool(whole("motor_board_off")),
                       motor_board_cutouts=whole("motor_board_cutouts"), error=whole("error"),
                       motor_rad=(angles[0], angles[1], angles[2]), var=var)
