"""Where a debugged run stops, and who attaches when (``crslab debug``).

Every stop crslab asks for happens between two ticks, before the ``lab()`` call of the tick it
names: the run's chunks end there (a ``--break-tick`` or ``--break-time``, or the first
``lab()`` call when no break is given), or the C loop ends its chunk before the first tick
whose ``lab()`` call begins with the ``--break-when`` condition true (``CRS_RUN_BREAK``,
csrc/board/debug.c). The worker is idle there; nothing of the tick has run yet.

- **gdb on the terminal** attaches before the first tick (so ``--debug-on-crash`` catches a
  crash anywhere) and runs with the lab. At the break the worker calls ``crs_debug_break``,
  where gdb arms a temporary breakpoint on ``lab()`` and goes on: it stops inside ``lab()`` at
  that tick. Ctrl-C is gdb's while it runs (it stops the lab where it is).
- **gdbserver** (an IDE) attaches at the break, so the IDE's first stop in ``lab()`` is at that
  tick (``tbreak lab`` in its setup, or a breakpoint set in the editor).

While the debugger holds the worker, the crslab process waits for its reply as for any chunk:
the plant, the scenario and every sink wait with it, so simulated time stands still, and the
hang watchdog is off from the attach on.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from crslab import os_support
from crslab.debug.gdb_commands import csrc_dir, gdb_argv, gdbserver_argv, setup_script
from crslab.debug.local_port import LocalPort
from crslab.debug.programs import debugger_for
from crslab.debug.tracer import GatedTracer, TracerError
from crslab.framework_facts import TICKS_PER_S
from crslab.worker.debug_setup import DebugSetup

if TYPE_CHECKING:
    from crslab.run.board_run import BoardRun
    from crslab.run.running import RunningLab

QUIT_TIMEOUT_S = 10.0
GDBSERVER_CHATTER = re.compile(r"^(Remote debugging using stdio|Attached; pid = \d+|Process .* attached)$")
"""What gdbserver says on its own start, which crslab's own line replaces."""


@dataclass(frozen=True)
class DebugPlan:
    """What the user asked of ``crslab debug``.

    ``break_tick``: stop in ``lab()`` at this tick (``--break-tick``, ``--break-time``);
    ``break_when``: at the first tick whose ``lab()`` call begins with this C condition true;
    neither: at the first ``lab()`` call, unless ``on_crash`` alone (then only a crash stops).
    ``gdbserver_port``: serve an IDE on localhost instead of gdb on the terminal (0: any free
    port). ``commands``: gdb commands run at the first stop; ``batch``: gdb exits after them and
    the run goes on to its end.
    """

    break_tick: int | None = None
    break_when: str | None = None
    on_crash: bool = False
    strict: bool = False
    gdbserver_port: int | None = None
    commands: tuple[str, ...] = ()
    batch: bool = False

    @property
    def console(self) -> bool:
        """gdb on the terminal (not gdbserver)."""
        return self.gdbserver_port is None


class DebugSession:
    """The debugger of one run: a :class:`~crslab.run.running.RunDebugger` and a
    :class:`~crslab.run.running.LiveControl` of ``BoardRun.run``. Use as a context manager
    around the :class:`~crslab.run.board_run.BoardRun`, created before it (the worker names the
    debugger's process as its tracer when it starts)."""

    def __init__(self, plan: DebugPlan, first_lab_tick: int, say: Callable[[str], None],
                 program: str | None = None) -> None:
        self.plan = plan
        self.say = say
        self._dir = tempfile.TemporaryDirectory(prefix="crslab-debug-")
        self.script = Path(self._dir.name) / "setup.gdb"
        self.port: int | None = None
        self.local: LocalPort | None = None
        self._reader: threading.Thread | None = None
        self._saved_sigint: object = None
        self._sigint_taken = False
        self.attached = False
        self._worker_pid = 0
        self.broke = False
        self.gone_noted = False
        if plan.break_tick is not None:
            self._pending: int | None = plan.break_tick
        elif plan.break_when is None and not (plan.on_crash and plan.console):
            self._pending = first_lab_tick
        else:
            self._pending = None
        program = program or debugger_for(plan.console)
        if plan.console:
            argv = gdb_argv(program, self.script, plan.commands, batch=plan.batch)
            self.tracer = GatedTracer(argv)
        else:
            argv = gdbserver_argv(program)
            self.local = LocalPort(int(plan.gdbserver_port or 0))
            self.port = self.local.port
            self.tracer = GatedTracer(argv, own_session=True, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE)
            assert self.tracer.process.stdin is not None and self.tracer.process.stdout is not None
            self.local.relay(self.tracer.process.stdin, self.tracer.process.stdout)
            self._reader = threading.Thread(target=self._read_gdbserver, daemon=True)
            self._reader.start()
        self.setup = DebugSetup(tracer_pid=self.tracer.pid, trap_fp=plan.on_crash and plan.strict)

    # -- lifecycle -------------------------------------------------------------------------------
    def __enter__(self) -> DebugSession:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def start(self, sim: BoardRun) -> None:
        """The worker is ready, before its first tick: gdb on the terminal attaches now."""
        if self.plan.console:
            self._attach(sim)
        if self._pending is not None and self._pending <= sim.tick:
            self.paused(sim, False)

    def close(self, run_over: bool = True) -> None:
        """The run is over: gdb in batch mode finishes its commands; otherwise the debugger, which
        has nothing left to debug, is ended."""
        if self.plan.console and self.attached:  # it quits once the lab's process has ended
            try:
                self.tracer.process.wait(QUIT_TIMEOUT_S)
            except subprocess.TimeoutExpired:
                pass
        self.tracer.stop()
        if self.local is not None:
            self.local.close()
        if self._reader is not None:
            self._reader.join(5.0)
        self._restore_sigint()
        self._dir.cleanup()

    # -- RunDebugger ------------------------------------------------------------------------------
    def pause_tick(self) -> int | None:
        """The break's tick, until the run stopped there."""
        return self._pending

    def paused(self, lab: RunningLab, condition_held: bool) -> None:
        """The run reached the break (before ``lab.tick``'s ``lab()`` call): stop in ``lab()``."""
        from crslab.run.board_run import BoardRun

        assert isinstance(lab, BoardRun)
        self._pending = None
        self.broke = True
        tick = lab.tick
        if condition_held:
            self.say(f"--break-when {self.plan.break_when!r} holds at tick {tick} "
                     f"(t = {tick / TICKS_PER_S:.3f} s)")
        if not self.attached:
            self._attach(lab)
        if self.plan.console:
            if self.tracer.running:
                lab.debug_break()
        else:
            program = os.path.realpath(sys.executable)
            self.say(f"lab() is held before tick {tick} (t = {tick / TICKS_PER_S:.3f} s); "
                     f"gdbserver listens on localhost:{self.port}: attach your IDE (docs/debugging.md; "
                     f"its program is {program}) "
                     f"or run gdb -ex 'target remote localhost:{self.port}'")

    def unreached(self) -> str | None:
        """After the run: the break it never reached (a ``--break-when`` that never held), in words."""
        if self._pending is None and self.plan.break_when is not None and not self.broke:
            return f"--break-when {self.plan.break_when!r} never held: the run ended without stopping"
        return None

    # -- LiveControl ------------------------------------------------------------------------------
    def serve(self, lab: RunningLab) -> None:
        """After every chunk: once the debugger has let go of the lab (quit, detach, the end of
        ``--batch``), the run goes on alone. A chunk cannot end while the debugger holds the lab
        stopped, so the first chunk after a detach sees it."""
        if not self.attached or self.gone_noted:
            return
        if os_support.tracer_of(self._worker_pid) != self.tracer.pid:
            self.gone_noted = True
            self._restore_sigint()
            name = "gdb" if self.plan.console else "your debugger"
            self.say(f"{name} has let go of the lab; it runs on to the end of the run"
                     + ("" if self.plan.batch else " (Ctrl-C ends it)"))

    # -- attaching --------------------------------------------------------------------------------
    def _attach(self, sim: BoardRun) -> None:
        report = Path(sim.sanitizer_dir) / "report.txt" if sim.sanitizer_dir else None
        self.script.write_text(setup_script(csrc_dir(), lab_file=sim.config.build.source.absolute(),
                                            sanitizer_report=report, batch=self.plan.batch))
        if self.plan.console:  # Ctrl-C belongs to gdb now: it stops the lab where it is
            self._saved_sigint = signal.signal(signal.SIGINT, signal.SIG_IGN)
            self._sigint_taken = True
        sys.stdout.flush()
        self.tracer.release(sim.worker_pid)
        try:
            self.tracer.wait_attached(sim.worker_pid)
        except TracerError:
            self._restore_sigint()
            raise
        self.attached = True
        self._worker_pid = sim.worker_pid
        sim.deadline_s = None  # the debugger holds the lab as long as it likes

    def _read_gdbserver(self) -> None:
        stream = self.tracer.process.stderr
        assert stream is not None
        for raw in stream:
            line = raw.decode(errors="replace").rstrip("\n")
            if line and not GDBSERVER_CHATTER.match(line):
                print(f"gdbserver: {line}", file=sys.stderr, flush=True)

    def _restore_sigint(self) -> None:
        if self._sigint_taken:
            saved = self._saved_sigint
            signal.signal(signal.SIGINT, saved if saved is not None else signal.default_int_handler)
            self._sigint_taken = False
