"""The crslab side of a run: a :class:`BoardRun` starts the worker, asks it for chunks of ticks,
hands what the board printed and everything else the run reports to one sink, and ends with one
:class:`~crslab.run.status.RunResult`.

Its parts each have a module: the worker process, started and watched
(:mod:`crslab.run.worker_process`); the messages on the pipe, checked once
(:mod:`crslab.worker.worker_messages`); the shared block the board prints into
(:mod:`crslab.run.shared_block`); the words for a run that ended early
(:mod:`crslab.run.diagnosis`); the length of chunks and the wall clock (:mod:`crslab.run.pacing`).

Time: tick k is at t = k ms (tick 0 is t = 0). Where chunks begin and end never changes what the
lab sees, so the transcript is the same at any speed. Serial bytes come with the tick during which
they left the board (the board's serial line sends 11.52 characters per ms); what is still on its
way out when a run ends is handed on last, marked with the tick the run ended at.
"""

from __future__ import annotations

import dataclasses
import pathlib
import signal
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager, nullcontext

import numpy as np

from crslab._bindings import constants
from crslab.framework_facts import TICKS_PER_S
from crslab.run import diagnosis, termination
from crslab.run.board_client import DEFAULT_DEADLINE_S, BoardClient, BoardHandle, InstanceNotOpened
from crslab.run.diagnosis import Ending
from crslab.run.firmware_trap import diagnose
from crslab.run.host_ports import PortExchange
from crslab.run.pacing import Pacer
from crslab.run.running import LiveControl, PacedControl, RunDebugger
from crslab.run.status import ExitStatus, RunResult, RunStatus
from crslab.run.worker_process import NO_LIMITS, Limits
from crslab.scenario.expect_events import Judge
from crslab.sinks.sink import FanOut, Sink
from crslab.worker import worker_messages
from crslab.worker.config import RunConfig
from crslab.worker.debug_setup import DebugSetup
from crslab.worker.run_stats import RunStats

__all__ = ["DEFAULT_DEADLINE_S", "NO_LIMITS", "CtrlC", "Limits", "RunError", "BoardRun"]


class RunError(Exception):
    """The run could not start (the worker failed before the first tick); ``status`` says how
    (crashed, or forbidden when a constructor tried what the sandbox refuses)."""

    def __init__(self, message: str, status: RunStatus = RunStatus.CRASHED,
                 exit_status: ExitStatus | None = None) -> None:
        super().__init__(message)
        self.status = status
        self.exit_status = exit_status if exit_status is not None else status.exit_status
        """The command's exit status: the status's, or bad input (2) when an input file is to blame."""


def _world_refused(config: RunConfig) -> bool:
    """Whether MuJoCo refuses the scene of ``config``'s world, as a worker said: a WebAssembly
    worker runs no lab code before it says so; a native one may have (a constructor), so this
    process asks MuJoCo itself before it blames the world file rather than the lab."""
    if not config.build.native:
        return True
    from crslab.world.scene import load_scene

    try:
        load_scene(config.world)
    except ValueError:
        return True
    return False


class CtrlC:
    """Ctrl-C (SIGINT) during a run, in the main thread: raised as ``KeyboardInterrupt`` at once,
    except while a chunk's bytes are being handed to the sinks (:meth:`held`) and once the run
    ends (:attr:`holding` set for good), where it waits until every sink has them, so stdout and
    the transcript never differ. Elsewhere (another thread, a handler of the caller's own) it
    leaves SIGINT alone."""

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


class _Printed:
    """What a run's sink gets of the serial bytes: everything up to the output limit (``cap``
    bytes); what the lab printed beyond it, lost or wrote with printf only counts."""

    def __init__(self, sink: Sink, cap: int) -> None:
        self.sink, self.cap = sink, cap
        self.bytes = 0
        self.console_seen = 0

    def serial(self, tick: int, data: bytes) -> None:
        keep = data[: max(0, self.cap - self.bytes)]
        self.bytes += len(data)
        if keep:
            self.sink.on_serial(tick, keep)

    def console(self, total: int) -> None:
        """The lab's printf has written ``total`` bytes so far (counted, never shown)."""
        self.bytes += total - self.console_seen
        self.console_seen = total

    @property
    def over(self) -> bool:
        """More than the limit."""
        return self.bytes > self.cap


class BoardRun:
    """A running lab: ``with BoardRun(config) as sim: sim.run(end_tick, sink, ...)``.

    ``debug`` prepares the worker for a debugger (``crslab debug``): the process it names may
    trace it. ``deadline_s`` None never calls the lab hung (a debugger holds it as long as it
    likes). ``on_started()`` is called once the worker process exists, while it loads the plant
    and the lab: what it starts overlaps the worker's start-up (threads may start then: the fork
    is done). ``worker``: open the run as an instance of that worker (a WebAssembly one other runs
    share: a server's) instead of starting a worker of its own.
    """

    def __init__(self, config: RunConfig, *, deadline_s: float | None = DEFAULT_DEADLINE_S,
                 limits: Limits = NO_LIMITS, debug: DebugSetup | None = None,
                 on_started: Callable[[], None] | None = None, worker: BoardClient | None = None) -> None:
        self.config = config
        self._deadline_s = deadline_s
        self.debug = debug
        self.limits = limits
        self.lab_name = config.build.source.name
        self.tick = 0
        self.stats = RunStats()
        self.serial_dropped = 0
        """Bytes that left the board but never reached the sinks: more in one chunk than the shared
        block holds (``CRS_SERIAL_CAPACITY`` bytes, ``CRS_MARK_CAPACITY`` ticks). The serial line's
        11.52 characters per ms keep a chunk far below that. In ``stats`` too."""
        self.motor_board_events: list[worker_messages.MotorBoardEvent] = []
        """The motor board's cut-outs so far. In ``stats`` too."""
        self.judge = Judge(config.scenario.events, config.scenario.source)
        """The scenario's expectations, judged as the worker's observations arrive."""
        self.symbols = 0
        self._own_worker = worker is None
        try:
            if worker is None:
                self.board_client = BoardClient(config, deadline_s=deadline_s, limits=limits, debug=debug,
                                                on_started=on_started)
                assert self.board_client.first is not None
                self.board: BoardHandle = self.board_client.first
            else:
                self.board_client = worker
                self.board = worker.open(config, deadline_s=deadline_s)
        except InstanceNotOpened as exc:
            reply = exc.reply
            if isinstance(reply, worker_messages.Trapped):
                reply = _trapped(reply.trap, self.lab_name, deadline_s, 0)
            elif isinstance(reply, worker_messages.Failed):
                if reply.file and _world_refused(config):  # the world file's fault, not the lab's
                    raise RunError(reply.message, RunStatus.CRASHED, ExitStatus.BAD_INPUT) from None
                reply = Ending(RunStatus.CRASHED, 0, f"{self.lab_name}: {reply.message}")
            assert isinstance(reply, Ending)
            raise RunError(reply.message, reply.status) from None
        self.block = self.board.block
        self.worker = self.board_client.process
        self.sanitizer_dir = self.worker.sanitizer_dir
        self.symbols = self.board.symbols

    @property
    def deadline_s(self) -> float | None:
        """How long one lab() or printing() call may take before the run ends hung (s); None: as
        long as it likes (a debugger holding the lab)."""
        return self._deadline_s

    @deadline_s.setter
    def deadline_s(self, value: float | None) -> None:
        self._deadline_s = value
        board = getattr(self, "board", None)
        if board is not None:  # the instance's runs are watched with it from the next one on
            board.deadline_s = value

    @property
    def worker_pid(self) -> int:
        """The process id of the worker (the process that runs the lab)."""
        return self.worker.pid

    @property
    def defines_lab(self) -> bool:
        """Whether the lab file defines ``lab()`` (the board would not link without one)."""
        return bool(self.symbols & constants.CRS_LAB_HAS_LAB)

    # -- lifecycle ---------------------------------------------------------------------------
    def __enter__(self) -> BoardRun:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Stop the instance and its worker, unless the worker is shared (it leaves no process
        behind), and free the shared block."""
        if self.board_client.alive:
            stopped = self.board_client.stop(self.board)
            if stopped is not None:
                self.stats = stopped.stats
        if self._own_worker:
            self.board_client.close()
        self.block.close()

    # -- the running lab (crslab.run.running.RunningLab) ---------------------------------------
    def _ask(self, request: worker_messages.Request) -> float | list[float] | None:
        reply = self.board_client.ask(self.board, request)
        if isinstance(reply, Ending):
            raise RunError(reply.message)
        if isinstance(reply, worker_messages.Error):
            raise KeyError(reply.message)
        return reply.value

    def get(self, name: str) -> float | list[float]:
        """Read a watched variable of the running lab (between ticks)."""
        value = self._ask(worker_messages.Get(self.board.id, name))
        assert value is not None
        return value

    def set(self, name: str, value: float, index: int | None = None) -> None:
        """Write a watched variable (or one array element) of the running lab, between ticks."""
        self._ask(worker_messages.Set(self.board.id, name, index, float(value)))

    def exchange(self, port: str, incoming: bytes) -> PortExchange:
        """Between chunks: what left the board on host port ``port`` (``SerialB``, ``SerialC``)
        since the last call; ``incoming`` goes to its receiver from the next tick on (as much as
        its inbox takes now: :attr:`PortExchange.taken`)."""
        return self.block.exchange(port, incoming)

    def push(self, body_forces: np.ndarray) -> None:
        """Apply a force and torque to each body (MuJoCo ``xfrc_applied``, world frame, N and N.m)
        from the next tick on, until the next push: MuJoCo's viewer passes the mouse's drag."""
        self._ask(worker_messages.Push(self.board.id, np.asarray(body_forces, dtype=float).tolist()))

    def debug_break(self) -> None:
        """Have the worker call ``crs_debug_break``: the debugger attached to it stops there and
        arms its breakpoint on ``lab()``, so it stops in the next ``lab()`` call (this tick's)."""
        self._ask(worker_messages.Break(self.board.id))

    # -- running -----------------------------------------------------------------------------
    def run(
        self,
        end_tick: int,
        sink: Sink | None = None,
        *,
        speed: float | None = None,
        controls: Sequence[LiveControl] = (),
        debugger: RunDebugger | None = None,
    ) -> RunResult:
        """Run to ``end_tick``, handing everything the run reports to ``sink`` (see
        :mod:`crslab.sinks.sink` for what and in which order); ``speed`` None is as fast as
        possible, else x real time. A run that reaches its end with a failed expectation ends
        ``unmet``; the result's ``expectations`` say how each went, ``stats.motor_board_events``
        lists the motor board's cut-outs.

        After every chunk of ticks, once ``sink`` took it, each of ``controls`` is served: the
        worker is idle then, so they may call :meth:`get`, :meth:`set`, :meth:`push` and
        :meth:`exchange` (live variables, the viewer's mouse, the host ports); a
        :class:`~crslab.run.running.PacedControl` among them (the serial bridge while a host
        program is attached) shortens the chunks to what it asks, and is served again right
        before the next chunk when the run waited for the wall clock.

        With a ``debugger`` (``crslab debug``) chunks are short and end at the tick it names,
        where it is called; time spent stopped in the debugger is not made up for: pacing starts
        again from where the lab resumed.
        """
        run = self.start(end_tick, sink, Pacer(speed, self.tick, debugger), controls)
        with CtrlC() as ctrl_c:
            try:
                try:
                    ending = self._chunks(run, ctrl_c)
                finally:
                    ctrl_c.holding = True  # the run ends: a Ctrl-C now lets the last bytes out
            except KeyboardInterrupt as exc:
                self.worker.kill()
                tick = self.block.tick
                how = f"terminated ({exc.name})" if isinstance(exc, termination.Terminated) else "interrupted"
                ending = Ending(RunStatus.INTERRUPTED, tick, f"{how} at t = {tick / TICKS_PER_S:.3f} s")
            return run.ended(ending)  # (its sinks' on_end too: a Ctrl-C now waits for the report)

    def start(self, end_tick: int, sink: Sink | None, pacer: Pacer,
              controls: Sequence[LiveControl] = ()) -> ChunkedRun:
        """A run to ``end_tick`` taken chunk by chunk by its caller (:meth:`run` is one such caller,
        a server that runs many labs in one worker another: crslab/serve/run_host.py)."""
        # a caller's FanOut as it is (one wrapping it would forward each of a chunk's calls twice)
        out = sink if isinstance(sink, FanOut) else FanOut([sink or Sink()])
        return ChunkedRun(self, end_tick, out, pacer, controls)

    def _chunks(self, run: ChunkedRun, ctrl_c: CtrlC) -> Ending:
        """Run chunk after chunk to the run's end; how the run ended."""
        pacer = run.pacer
        while not run.done:
            target, pause = run.next_chunk()
            reply = self.run_chunk(target)
            ending = run.took(reply, ctrl_c.held)
            if ending is not None:
                return ending
            broke = reply.code == constants.CRS_RUN_BREAK  # (took returned: reply is a Ran)
            if pacer.debugger is not None and (broke or self.tick == pause):
                pacer.debugger.paused(self, broke)
            waited = pacer.wait(self.tick)
            if waited.slept:
                for control in run.controls:  # what a host sent while we slept: this tick
                    if isinstance(control, PacedControl):
                        control.serve(self)
            if waited.behind is not None:
                run.sink.on_behind(waited.behind)
        return Ending(RunStatus.OK, self.tick)

    def run_chunk(self, target: int) -> worker_messages.Ran | Ending:
        """Have the worker run the lab to ``target``: its reply, or how the worker ended."""
        return self.board_client.run([(self.board, target)])[0]


_NOTHING_HELD = nullcontext()
"""What :meth:`ChunkedRun.took` holds a chunk's hand-over in when no Ctrl-C is held back (a run
host's: made once, not once a chunk)."""


class ChunkedRun:
    """One run of a :class:`BoardRun`, taken chunk by chunk: where the next chunk ends
    (:meth:`next_chunk`), what a chunk's reply hands to the sink and the controls (:meth:`took`),
    and the result once it ended (:meth:`ended`). The worker is asked by the caller, so a server
    may run many labs of one worker forward in one request (crslab/serve/run_host.py).

    However a run ends (its end tick, a trap, the output limit, a Stop, Ctrl-C, a worker that
    died or was killed), the sink gets every tick it ran: the board writes each tick's scope row
    and serial bytes into the shared block, which outlives the worker, and :meth:`ended` takes what
    is left there."""

    def __init__(self, sim: BoardRun, end_tick: int, sink: Sink, pacer: Pacer,
                 controls: Sequence[LiveControl]) -> None:
        self.sim = sim
        self.end_tick = end_tick
        self.sink = sink
        self.pacer = pacer
        self.controls = controls
        self.printed = _Printed(sink, sim.limits.output_bytes)
        self._logs = sim.config.log_signals
        self._world = not sim.config.world.is_free_air
        self.rows_in_block = False
        """The scope rows stay in the shared block, for a sink that takes them there (a run host's
        page stream: :meth:`crslab.sinks.page_stream.BrowserStream.rows_from`), and no sink gets
        them through ``on_log``."""

    @property
    def done(self) -> bool:
        """Whether the run reached its end tick."""
        return self.sim.tick >= self.end_tick

    def next_chunk(self) -> tuple[int, int | None]:
        """Where the next chunk ends, and the tick a debugger asks to stop before (None)."""
        return self.pacer.next_chunk(self.sim.tick, self.end_tick, self.controls)

    def took(self, reply: worker_messages.Ran | Ending,
             held: Callable[[], AbstractContextManager[None]] = nullcontext, *,
             serve: bool = True) -> Ending | None:
        """Hand a chunk's reply (or the worker's end) on: None while the run goes on, else how it
        ended (a trap, the output limit, a stop, a strict NaN, a printf overflow, the worker gone). ``held``
        holds a Ctrl-C back while the sinks take the chunk. ``serve`` False leaves the controls to
        :meth:`serve_controls` (a caller still reading its worker's other replies, whose controls
        must not ask the worker meanwhile)."""
        sim, sink = self.sim, self.sink
        if isinstance(reply, Ending):
            return reply  # (what the worker left in the shared block: :meth:`ended`)
        sim.tick, sim.stats = reply.tick, reply.stats
        if reply.code == constants.CRS_RUN_TRAPPED:
            return _trapped(reply.trap or {}, sim.lab_name, sim.deadline_s, sim.tick, sim.config.build.image)
        try:
            judged = [sim.judge.observed(seen) for seen in reply.observations]
        except ValueError as exc:
            return sim.worker.tampered(f"it sent an observation crslab cannot read: {exc}")
        for event in reply.motor_board_events:
            sim.motor_board_events.append(event)
            sink.on_motor_board(*event)
        for outcome in judged:
            if outcome is not None:
                sink.on_expectation(outcome)
        with held() if held is not nullcontext else _NOTHING_HELD:  # every sink gets all of it, or none
            self._take_log()
            self._take_printed()
            if not self.printed.over:
                sink.flush()
                sink.on_reached(sim.tick)
        if self.printed.over:
            return diagnosis.output_limit(sim.lab_name, sim.tick, self.printed.cap)
        if serve:
            self.serve_controls()
        if reply.code == constants.CRS_RUN_STOPPED:  # the page's Stop, or the page went
            return diagnosis.stopped(sim.tick)
        if reply.code == constants.CRS_RUN_NAN_STRICT:
            return diagnosis.nan_strict(sim.lab_name, sim.stats, sim.tick)
        if reply.code == constants.CRS_RUN_PRINTF_OVERFLOW:
            return diagnosis.print_overflow(sim.lab_name, sim.stats, sim.tick,
                                            sim.config.build.printf_buffer_chars)
        return None

    def serve_controls(self) -> None:
        """Serve each control once (the worker is idle: they may ask it)."""
        for control in self.controls:
            control.serve(self.sim)

    def ended(self, ending: Ending) -> RunResult:
        """The run's result, the last of what it left in the shared block handed on first (the
        scope rows of every tick it ran; the bytes still on the serial line, marked with the tick
        the run ended at), the counters, the expectations (a run that reached its end with one
        failed is ``unmet``); then the result to the sinks (``on_end``: the end-of-run report,
        among others)."""
        sim, printed = self.sim, self.printed
        self._take_log(only_rows=True)  # the rows the last chunk left, whether the worker answered or not
        self._take_printed()
        line = sim.block.take_line()
        if line:
            printed.serial(ending.tick, line)
        stats = dataclasses.replace(sim.stats, serial_dropped=sim.serial_dropped, lab_symbols=sim.symbols,
                                    motor_board_events=tuple(sim.motor_board_events),
                                    console_bytes=self._console_bytes())
        expectations = sim.judge.results()
        failed = sum(bool(e.failures) for e in expectations)
        status, message = ending.status, ending.message
        if status is RunStatus.OK and failed:
            status = RunStatus.UNMET
            scenario = sim.config.scenario.name
            message = f"{failed} of {len(expectations)} expectations of scenario {scenario} failed"
        result = RunResult(status, ending.tick, message, stats, lab_file=sim.config.build.source,
                           wall_s=self.pacer.elapsed_s(), expectations=expectations)
        self.sink.on_end(result)
        return result

    def _take_log(self, *, only_rows: bool = False) -> None:
        """Hand the scope rows the board wrote since the last time to the sink (when the run logs
        them): after a chunk, as many as it left (none, perhaps); ``only_rows``: only if there
        are any (a run that ended after its last chunk was handed on has none)."""
        if self._logs and not self.rows_in_block:
            rows = self.sim.block.take_log(world=self._world)
            if len(rows["tick"]) or not only_rows:
                self.sink.on_log(rows)

    def _take_printed(self) -> None:
        """Hand what the board printed since the last time to the sink, through the output limit
        (what was lost counts toward the limit too, and so do the bytes the lab's printf wrote:
        counted, never shown)."""
        sim = self.sim
        dropped = sim.block.drain(self.sink.on_print, self.printed.serial)
        sim.serial_dropped += dropped  # more in one chunk than the shared block holds
        self.printed.bytes += dropped
        self.printed.console(self._console_bytes())

    def _console_bytes(self) -> int:
        return max(self.sim.stats.console_bytes, self.sim.worker.console_bytes)


def _trapped(trap: dict, lab_name: str, deadline_s: float | None, tick: int,
             image: pathlib.Path | None = None) -> Ending:
    """A WebAssembly firmware that stopped (the worker survives it and says how)."""
    status, message = diagnose(trap, lab_name, deadline_s=deadline_s, image=image)
    return Ending(status, tick, message)
