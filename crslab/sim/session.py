"""The crslab side of a run: starts the worker, paces it, reads what the board printed, and
turns a worker that crashes, exits or hangs into one line of diagnosis.

Time: tick k is at t = k ms (tick 0 is t = 0). Chunks of ticks are requested from the worker;
where chunks begin and end never changes what the lab sees, so the transcript is the same at
any speed.
"""

from __future__ import annotations

import ctypes
import multiprocessing as mp
import os
import signal
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from crslab.sim.board_ffi import board_ffi, shared_size
from crslab.sim.config import SimConfig

SerialSink = Callable[[int, bytes], None]
LogSink = Callable[[dict[str, np.ndarray]], None]

PHASE_WHERE = {0: "between ticks", 1: "in lab()", 2: "in printing()", 3: "in the physics step"}
DEFAULT_DEADLINE_S = 2.0
READY_TIMEOUT_S = 60.0
REALTIME_SLICE_TICKS = 20
FAST_SLICE_TICKS = 20_000


class SimError(Exception):
    """The run could not start (the worker failed before the first tick)."""


@dataclass
class RunResult:
    """How a run ended: ``status`` is ok, crashed, exited, hung, nan or interrupted."""

    status: str
    end_tick: int
    message: str = ""
    stats: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """True when the run reached its end normally."""
        return self.status == "ok"


def _child(conn: object, config: SimConfig, shared_path: str) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the crslab process's to handle
    try:  # die with the crslab process, whatever kills it
        ctypes.CDLL(None).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    from crslab.sim.worker import serve

    serve(conn, config, shared_path)  # type: ignore[arg-type]
    os._exit(0)


class Simulation:
    """A running lab: ``with Simulation(config) as sim: sim.run(end_tick, ...)``."""

    def __init__(self, config: SimConfig, *, deadline_s: float = DEFAULT_DEADLINE_S) -> None:
        self.config = config
        self.deadline_s = deadline_s
        self.lab_name = config.build.source.name
        self.ffi = board_ffi()
        shm_dir = "/dev/shm" if os.path.isdir("/dev/shm") else None
        fd, self.shared_path = tempfile.mkstemp(prefix="crslab-", dir=shm_dir)
        os.ftruncate(fd, shared_size())
        import mmap

        self._shared_mm = mmap.mmap(fd, 0)
        os.close(fd)
        self.shared = self.ffi.cast("crs_shared *", self.ffi.from_buffer(self._shared_mm))
        self.tick = 0
        self.stats: dict = {}
        self.symbols = 0
        sys.stdout.flush()
        sys.stderr.flush()
        ctx = mp.get_context("fork")
        self._conn, child_conn = ctx.Pipe()
        self.process = ctx.Process(target=_child, args=(child_conn, config, self.shared_path), daemon=True)
        self.process.start()
        child_conn.close()
        reply = self._wait_reply(READY_TIMEOUT_S, during_setup=True)
        if isinstance(reply, RunResult):
            self.close()
            raise SimError(reply.message)
        self.symbols = reply[1]

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
                    reply = self._conn.recv()
                    self.stats = reply[1] or self.stats
            except (OSError, EOFError, BrokenPipeError):
                pass
            self.process.join(2.0)
            if self.process.is_alive():
                self.process.kill()
        self.process.join()
        self._conn.close()
        try:
            os.unlink(self.shared_path)
        except FileNotFoundError:
            pass

    # -- serial ------------------------------------------------------------------------------
    def drain_serial(self, sink: SerialSink | None) -> None:
        """Hand every serial_printf call's bytes since the last drain to ``sink(tick, bytes)``."""
        sh = self.shared
        n_bytes, n_marks = int(sh.serial_len), int(sh.mark_count)
        if n_bytes and sink is not None:
            raw = bytes(self.ffi.buffer(sh.serial, n_bytes))
            offsets = [int(sh.mark_offset[i]) for i in range(n_marks)] + [n_bytes]
            for i in range(n_marks):
                sink(int(sh.mark_tick[i]), raw[offsets[i]:offsets[i + 1]])
        sh.serial_len = 0
        sh.mark_count = 0

    # -- watched variables -------------------------------------------------------------------
    def _ask(self, msg: tuple) -> object:
        self._conn.send(msg)
        reply = self._wait_reply(None)
        if isinstance(reply, RunResult):
            raise SimError(reply.message)
        if reply[0] == "error":
            raise KeyError(reply[1])
        return reply[1]

    def get(self, name: str) -> float | list[float]:
        """Read a watched variable of the running lab (between ticks)."""
        return self._ask(("get", name))  # type: ignore[return-value]

    def set(self, name: str, value: float, index: int | None = None) -> None:
        """Write a watched variable (or one array element) of the running lab, between ticks."""
        self._ask(("set", name, index, float(value)))

    # -- running -----------------------------------------------------------------------------
    def _diagnose_death(self) -> RunResult:
        self.process.join(1.0)
        code = self.process.exitcode
        tick = int(self.shared.tick)
        where = PHASE_WHERE.get(int(self.shared.phase), "")
        at = f"at tick {tick} (t = {tick / 1000:.3f} s)"
        if code is not None and code < 0:
            name = signal.Signals(-code).name
            return RunResult("crashed", tick, f"{self.lab_name} crashed ({name}) {where} {at}", self.stats)
        return RunResult("exited", tick, f"{self.lab_name} called exit({code}) {where} {at}", self.stats)

    def _wait_reply(self, timeout_s: float | None, during_setup: bool = False) -> tuple | RunResult:
        start = time.monotonic()
        while True:
            try:
                if self._conn.poll(0.05):
                    return self._conn.recv()
            except (EOFError, ConnectionResetError):
                pass
            if not self.process.is_alive():
                if during_setup:
                    self.process.join(1.0)
                    code = self.process.exitcode
                    how = signal.Signals(-code).name if code and code < 0 else f"exit status {code}"
                    return RunResult("crashed", 0, f"{self.lab_name} could not be loaded ({how})")
                return self._diagnose_death()
            phase = int(self.shared.phase)
            if phase in (1, 2):
                busy_s = (time.monotonic_ns() - int(self.shared.phase_start_ns)) / 1e9
                if busy_s > self.deadline_s:
                    tick = int(self.shared.tick)
                    self.process.kill()
                    self.process.join()
                    func = "lab()" if phase == 1 else "printing()"
                    return RunResult(
                        "hung", tick,
                        f"{self.lab_name} hung: {func} did not return within {self.deadline_s:g} s "
                        f"at tick {tick} (t = {tick / 1000:.3f} s)", self.stats)
            if timeout_s is not None and time.monotonic() - start > timeout_s:
                self.process.kill()
                return RunResult("crashed", int(self.shared.tick),
                                 f"{self.lab_name}: the worker stopped answering")

    def run(
        self,
        end_tick: int,
        *,
        speed: float | None = None,
        on_serial: SerialSink | None = None,
        on_log: LogSink | None = None,
        on_behind: Callable[[float], None] | None = None,
    ) -> RunResult:
        """Run to ``end_tick``; ``speed`` None is as fast as possible, else x real time."""
        wall0, tick0 = time.monotonic(), self.tick
        warned = False
        try:
            while self.tick < end_tick:
                step = FAST_SLICE_TICKS if speed is None else max(1, int(REALTIME_SLICE_TICKS * speed))
                target = min(end_tick, self.tick + step)
                self._conn.send(("run", target))
                reply = self._wait_reply(None)
                if isinstance(reply, RunResult):
                    self.drain_serial(on_serial)
                    return reply
                _, code, self.tick, self.stats, log = reply
                self.drain_serial(on_serial)
                if log is not None and on_log is not None:
                    on_log(log)
                if code == 3:  # CRS_RUN_NAN_STRICT
                    return RunResult("nan", self.tick, "", self.stats)
                if speed is not None:
                    due = wall0 + (self.tick - tick0) / 1000.0 / speed
                    lag = time.monotonic() - due
                    if lag < 0:
                        time.sleep(-lag)
                    elif lag > 0.5 and not warned and on_behind is not None:
                        sim_s = (self.tick - tick0) / 1000.0
                        on_behind(sim_s / (time.monotonic() - wall0))
                        warned = True
        except KeyboardInterrupt:
            self.process.kill()
            self.process.join()
            self.drain_serial(on_serial)
            tick = int(self.shared.tick)
            return RunResult("interrupted", tick, f"interrupted at t = {tick / 1000:.3f} s", self.stats)
        return RunResult("ok", self.tick, "", self.stats)
