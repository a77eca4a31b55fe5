"""One line for each way a lab can end a run early: its worker died (a signal, ``exit()``, a
sanitizer's finding, the sandbox's refusal, a resource limit), hung, printed too much, overflowed
the board's print buffer, returned a NaN under ``--strict``, or wrote into crslab's pipe.

Each is an :class:`Ending`: the status, the tick and the words, read from what survives the worker
(its exit status, the shared block, the sanitizer's report) and never from anything it said. A
WebAssembly firmware's own traps are worded by :mod:`crslab.run.firmware_trap`.

>>> hung("lab.c", "printing()", 5100, 0.5).message
'lab.c hung: printing() did not return within 0.5 s at tick 5100 (t = 5.100 s)'
"""

from __future__ import annotations

import os
import signal
from pathlib import Path
from typing import NamedTuple

from crslab._bindings import constants
from crslab.framework_facts import TICKS_PER_S
from crslab.run.sanitizer import summarize_sanitizer_report
from crslab.run.shared_block import SharedBlock
from crslab.run.status import RunStatus
from crslab.untrusted_text import for_terminal
from crslab.worker.run_stats import RunStats


class Ending(NamedTuple):
    """How a run ended: its status, the tick it ended at and the one line that says why."""

    status: RunStatus
    tick: int
    message: str = ""


def at_tick(tick: int) -> str:
    """When, in a diagnosis.

    >>> at_tick(5123)
    'at tick 5123 (t = 5.123 s)'
    """
    return f"at tick {tick} (t = {tick / TICKS_PER_S:.3f} s)"


def phase_where(phase: int) -> str:
    """Where the worker was, from the phase it wrote (``CRS_PHASE_*``).

    >>> phase_where(constants.CRS_PHASE_PRINTING)
    'in printing()'
    """
    c = constants
    return {c.CRS_PHASE_IDLE: "between ticks", c.CRS_PHASE_LAB: "in lab()",
            c.CRS_PHASE_PRINTING: "in printing()", c.CRS_PHASE_PHYSICS: "in the physics step",
            c.CRS_PHASE_LOADING: "in a constructor or static initializer"}.get(phase, "")


def phase_function(phase: int) -> str:
    """The lab's function a deadline was running out in.

    >>> phase_function(constants.CRS_PHASE_LAB)
    'lab()'
    """
    return "printing()" if phase == constants.CRS_PHASE_PRINTING else "lab()"


class WorkerDeath(NamedTuple):
    """What is known of a worker that died: its exit code (``-signal``), the block it leaves, and
    the run's setting (debugged, limits) that changes the words."""

    lab_name: str
    exitcode: int | None
    block: SharedBlock
    memory_mb: int | None = None
    cpu_s: float | None = None
    debugged: bool = False
    trap_fp: bool = False
    sanitizer_report: str | None = None
    """The first sanitizer finding (:func:`sanitizer_finding`), if the run was sanitized."""


def refused(death: WorkerDeath) -> Ending | None:
    """The worker stopped by the sandbox: what the lab tried, where and when (None if not)."""
    record = death.block.refusal
    if not record.refused and death.exitcode != -signal.SIGSYS:
        return None
    from crslab.sandbox.refusal import tried

    block = death.block
    phase = int(record.phase) if record.refused else block.phase
    tick = int(record.tick) if record.refused else block.tick
    what = for_terminal(tried(record, parent_pid=os.getpid())) if record.refused else \
        "make a system call the sandbox refuses"
    at = "before the first tick" if phase == constants.CRS_PHASE_LOADING else at_tick(tick)
    return Ending(RunStatus.FORBIDDEN, tick, f"{death.lab_name} was stopped by the sandbox: it tried "
                  f"to {what} {phase_where(phase)} {at}")


def not_loaded(death: WorkerDeath) -> Ending:
    """The worker died before it was ready (before the first tick)."""
    found = refused(death)
    if found is not None:
        return found
    code = death.exitcode
    how = signal.Signals(-code).name if code and code < 0 else f"exit status {code}"
    return Ending(RunStatus.CRASHED, 0, f"{death.lab_name} could not be loaded ({how})")


def died(death: WorkerDeath) -> Ending:
    """The worker died during the run."""
    code, name, tick = death.exitcode, death.lab_name, death.block.tick
    where = phase_where(death.block.phase)
    at = at_tick(tick)
    report = death.sanitizer_report
    if report is not None:  # first: a sanitizer's own report may touch what the sandbox refuses
        where = "" if report.endswith("()") else f" {where}"
        return Ending(RunStatus.CRASHED, tick, f"{name}: {report}{where} {at}")
    found = refused(death)
    if found is not None:
        return found
    if code == -signal.SIGFPE and death.trap_fp:
        return Ending(RunStatus.CRASHED, tick, f"{name} raised a floating-point exception (SIGFPE) {where} "
                      f"{at}: an operation that made a NaN or an infinity (with --strict and "
                      "--debug-on-crash), or an integer division by zero")
    if code == -signal.SIGKILL and death.debugged:
        return Ending(RunStatus.CRASHED, tick, f"{name}'s process was killed (SIGKILL) {where} {at}: by the "
                      "debugger's kill, or by the system")
    if code == -signal.SIGXCPU:
        return Ending(RunStatus.CRASHED, tick, f"{name} used up its CPU-time limit ({death.cpu_s:g} s) "
                      f"{where} {at}")
    if code is not None and code < 0:
        hint = f"; its memory limit was {death.memory_mb} MB" if death.memory_mb else ""
        signame = signal.Signals(-code).name
        return Ending(RunStatus.CRASHED, tick, f"{name} crashed ({signame}) {where} {at}{hint}")
    return Ending(RunStatus.EXITED, tick, f"{name} called exit({code}) {where} {at}")


def sanitizer_finding(report_dir: str | None, source_name: str) -> str | None:
    """The first sanitizer finding in ``report_dir``, as one phrase naming the user's file and line."""
    if not report_dir:
        return None
    for path in sorted(Path(report_dir).glob("report.txt")):
        found = summarize_sanitizer_report(path.read_text(errors="replace"), source_name)
        if found:
            return found
    return None


def hung(lab_name: str, func: str, tick: int, deadline_s: float | None) -> Ending:
    """A ``lab()`` or ``printing()`` call that did not return (the worker was killed)."""
    within = f" within {deadline_s:g} s" if deadline_s is not None else ""
    return Ending(RunStatus.HUNG, tick, f"{lab_name} hung: {func} did not return{within} {at_tick(tick)}")


def stopped(tick: int) -> Ending:
    """The page asked its run to stop (its Stop, or it closed): the run ends at the tick it reached.

    >>> stopped(5123).message
    'stopped at t = 5.123 s'
    """
    return Ending(RunStatus.INTERRUPTED, tick, f"stopped at t = {tick / TICKS_PER_S:.3f} s")


def over_memory(lab_name: str, tick: int, phase: int, memory_mb: int | None) -> Ending:
    """A sanitized lab that used more resident memory than its limit (the worker was killed)."""
    return Ending(RunStatus.CRASHED, tick, f"{lab_name} used more than its memory limit ({memory_mb} MB) "
                  f"{phase_where(phase)} {at_tick(tick)}")


def output_limit(lab_name: str, tick: int, limit_bytes: int) -> Ending:
    """The lab printed more than the output limit: the run was cut off.

    >>> output_limit("flood.c", 6000, 20_000).message
    'flood.c printed more than 0.02 MB; the run was cut off at tick 6000 (t = 6.000 s)'
    """
    return Ending(RunStatus.OUTPUT_LIMIT, tick, f"{lab_name} printed more than {limit_bytes / 1e6:g} MB; "
                  f"the run was cut off {at_tick(tick)}")


def tampered(lab_name: str, what: str, tick: int) -> Ending:
    """The lab wrote into the pipe to crslab (it is unpickled by nobody); ``tick`` is an upper
    bound, as the worker may have run on a little since."""
    return Ending(RunStatus.FORBIDDEN, tick, f"{lab_name} was stopped by the sandbox: it tried to write "
                  f"into crslab's pipe ({what}) by tick {tick} (t = {tick / TICKS_PER_S:.3f} s)")


def nan_strict(lab_name: str, stats: RunStats, tick: int) -> Ending:
    """``--strict``: the lab returned a NaN or an infinity as a torque."""
    first, joint = stats.nan_first_tick, stats.nan_first_joint
    return Ending(RunStatus.NAN, tick, f"{lab_name} returned a NaN or Inf in tau{joint} {at_tick(first)} "
                  "and --strict is on")


def print_overflow(lab_name: str, stats: RunStats, tick: int, buffer_chars: int) -> Ending:
    """A serial_printf that overflowed the board's format buffer (the run ends at its tick).

    >>> print_overflow("long.c", RunStats(overflow_tick=4100, overflow_chars=300, overflow_phase=1), 4200,
    ...                136).message.split(";")[0]
    'long.c: a serial_printf in lab() at tick 4100 (t = 4.100 s) formatted 300 characters'
    """
    at = stats.overflow_tick if stats.overflow_tick >= 0 else tick
    where = phase_where(stats.overflow_phase)
    return Ending(RunStatus.CRASHED, at, f"{lab_name}: a serial_printf {where} {at_tick(at)} formatted "
                  f"{stats.overflow_chars} characters; the board's {buffer_chars}-byte "
                  f"serial_printf buffer holds {buffer_chars - 1} and a terminating NUL, so this line "
                  "overflows it and corrupts the board's memory")
