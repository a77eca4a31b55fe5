"""How a run ended: its :class:`RunStatus` (with the exit status and grade class that go with it)
and the one :class:`RunResult` every way of running a lab returns (``simulate``, ``crslab sim``,
``record``, ``check``, ``grade``).

The exit statuses are the README's table; a status's grade class is what ``crslab grade`` calls
a submission that ended that way (an ``ok`` run passes or mismatches, by its transcript).
A run that reached its end with a failed scenario expectation is ``unmet``: exit status 1, as a
mismatch, and its own grade class, whatever its transcript; its ``expectations`` say which.

>>> RunStatus.HUNG.exit_status, RunStatus.HUNG.grade_class
(<ExitStatus.HUNG: 4>, <GradeClass.HUNG: 'hung'>)
>>> RunStatus("exited").graded(matched=False), RunStatus.OK.graded(matched=True)
(<GradeClass.CRASHED: 'crashed'>, <GradeClass.PASS: 'pass'>)
>>> f"{RunStatus.OUTPUT_LIMIT}", RunStatus.OUTPUT_LIMIT == "output-limit"
('output-limit', True)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum, StrEnum
from pathlib import Path

import numpy as np

from crslab import serial_lines
from crslab.scenario.expect_events import ExpectOutcome
from crslab.worker.run_stats import RunStats


class ExitStatus(IntEnum):
    """The exit statuses of the ``crslab`` commands that run labs (README, "exit status")."""

    OK = 0
    MISMATCH = 1
    """``check``: the transcript differs; ``grade``: a submission did not pass; a scenario
    expectation failed."""
    BAD_INPUT = 2
    CRASHED = 3
    HUNG = 4
    NAN = 5
    OUTPUT_LIMIT = 6
    INTERRUPTED = 130


class GradeClass(StrEnum):
    """What ``crslab grade`` calls a submission."""

    PASS = "pass"
    MISMATCH = "mismatch"
    UNMET = "unmet"
    DOES_NOT_COMPILE = "does not compile"
    CRASHED = "crashed"
    HUNG = "hung"
    FORBIDDEN = "forbidden"


class RunStatus(StrEnum):
    """How a run ended. Each status carries its exit status and its grade class."""

    exit_status: ExitStatus
    grade_class: GradeClass

    def __new__(cls, value: str, exit_status: ExitStatus, grade_class: GradeClass) -> RunStatus:
        member = str.__new__(cls, value)
        member._value_ = value
        member.exit_status = exit_status
        member.grade_class = grade_class
        return member

    OK = "ok", ExitStatus.OK, GradeClass.PASS
    """The run reached its end."""
    UNMET = "unmet", ExitStatus.MISMATCH, GradeClass.UNMET
    """The run reached its end, and an expectation of the scenario failed."""
    CRASHED = "crashed", ExitStatus.CRASHED, GradeClass.CRASHED
    """The lab's process died: a signal, a sanitizer finding, its CPU-time limit."""
    EXITED = "exited", ExitStatus.CRASHED, GradeClass.CRASHED
    """The lab called ``exit()``."""
    HUNG = "hung", ExitStatus.HUNG, GradeClass.HUNG
    """``lab()`` or ``printing()`` did not return within the deadline."""
    FORBIDDEN = "forbidden", ExitStatus.CRASHED, GradeClass.FORBIDDEN
    """The lab tried to reach outside its run (files, processes, network)."""
    NAN = "nan", ExitStatus.NAN, GradeClass.CRASHED
    """A NaN or Inf torque with ``--strict``."""
    OUTPUT_LIMIT = "output-limit", ExitStatus.OUTPUT_LIMIT, GradeClass.CRASHED
    """The lab printed more than its output limit (a flood)."""
    INTERRUPTED = "interrupted", ExitStatus.INTERRUPTED, GradeClass.CRASHED
    """Ctrl-C."""
    NO_LAB = "no-lab", ExitStatus.BAD_INPUT, GradeClass.DOES_NOT_COMPILE
    """The lab file defines no ``lab()`` (it would not link on the board)."""
    BUILD_ERROR = "build-error", ExitStatus.BAD_INPUT, GradeClass.DOES_NOT_COMPILE
    """The lab file does not compile."""
    UNFIT = "unfit", ExitStatus.BAD_INPUT, GradeClass.MISMATCH
    """The scenario writes a variable the lab does not watch."""
    TIMEOUT = "timeout", ExitStatus.HUNG, GradeClass.HUNG
    """The whole run (building included) took longer than allowed and was stopped."""

    def graded(self, *, matched: bool) -> GradeClass:
        """The grade of a run that ended so and whose transcript did or did not match."""
        if self is RunStatus.OK:
            return GradeClass.PASS if matched else GradeClass.MISMATCH
        return self.grade_class


@dataclass
class RunResult:
    """A finished run: how it ended, what the board printed and the scope log when one was kept.

    ``calls`` holds ``(tick, bytes)`` per serial_printf call: its tick and the bytes of it that
    fit the board's transmit ring. ``sent`` holds the same bytes as they left the board:
    ``(tick, bytes)`` per tick whose millisecond carried any (11.52 characters per ms).
    ``stats`` holds the run's counters (:class:`~crslab.worker.run_stats.RunStats`: lab() timing,
    NaN notices, characters the transmit ring dropped, the motor board's cut-outs as
    ``motor_board_events``: ``(tick, joint, off)``);
    ``details`` the full diagnostics behind ``message`` (gcc's output); ``lab_file`` the lab that
    ran and ``wall_s`` the wall-clock seconds it took, when the caller timed it.
    ``expectations`` holds how each of the scenario's expectations went, in time order (those
    the run never reached last).
    """

    status: RunStatus
    end_tick: int = 0
    message: str = ""
    stats: RunStats = field(default_factory=RunStats)
    calls: list[tuple[int, bytes]] = field(default_factory=list)
    sent: list[tuple[int, bytes]] = field(default_factory=list)
    log: dict[str, np.ndarray] | None = None
    details: str = ""
    lab_file: Path | None = None
    wall_s: float = 0.0
    expectations: list[ExpectOutcome] = field(default_factory=list)
    habits: tuple[str, ...] = ()
    """The C89 habits the lab was built with, one line each saying what the board does
    (:mod:`crslab.lab.c89_habits`), when the caller built it (``crslab grade``)."""

    @property
    def ok(self) -> bool:
        """True when the run reached its end normally and met every expectation it reached."""
        return self.status is RunStatus.OK

    @property
    def failed_expectations(self) -> list[ExpectOutcome]:
        """The expectations that failed."""
        return [e for e in self.expectations if e.failures]

    def diagnosis(self) -> str:
        """Why the run is not ok, in full: the message (else the status), then one line per failed
        expectation condition.

        >>> why = "expected the motor board on, it was off"
        >>> failed = ExpectOutcome(6000, "cut.toml:9", "", failures=(why,))
        >>> run = RunResult(RunStatus.UNMET, message="1 of 1 expectations failed", expectations=[failed])
        >>> print(run.diagnosis())
        1 of 1 expectations failed
        t = 6.000 s: expected the motor board on, it was off (cut.toml:9)
        """
        lines = [self.message or str(self.status)]
        for e in self.failed_expectations:
            lines.extend(e.lines())
        return "\n".join(lines)

    @property
    def exit_status(self) -> ExitStatus:
        """The ``crslab`` exit status for a run that ended so."""
        return self.status.exit_status

    @property
    def transcript(self) -> bytes:
        """Every byte the board printed, exactly."""
        return b"".join(d for _, d in self.calls)

    def lines(self) -> list[str]:
        r"""The printed lines as text, without their line ends (:mod:`crslab.serial_lines`' rule).

        >>> RunResult(RunStatus.OK, calls=[(0, b"a 1\n\r"), (5, b"b")]).lines()
        ['a 1', 'b']
        """
        return [text for _, text in serial_lines.split(self.transcript)]
