"""A run's statistics, typed: the board's counters the worker reads out of ``crs_board``
(csrc/board/board.h) and what the crslab process counts beside them, as one frozen
:class:`RunStats` (``RunResult.stats``), read by attribute.

On the pipe they travel as a table of plain data (:meth:`RunStats.wire`); the crslab process reads
that table back in :mod:`crslab.worker.worker_messages` (``_stats``), which checks every value,
since a native lab may have written it.

>>> stats = RunStats(lab_calls=900, first_over_tick=(4100,), motor_board_events=((4600, 1, True),))
>>> stats.nan_first_tick, stats.wire()["first_over_tick"], stats.wire()["motor_board_events"]
(-1, [4100], [[4600, 1, 1]])
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class RunStats:
    """What a run counted. The board's counters (``crs_board``'s fields of the same names,
    :data:`BOARD_COUNTERS`) first; ``tick`` and below are the worker's view of the run; the last
    three are the crslab process's, set once the run has ended."""

    lab_calls: int = 0
    """How many times lab() was called."""
    lab_cost_total: int = 0
    """lab()'s cost summed over its calls, in :attr:`cost_unit`."""
    lab_cost_max: int = 0
    """lab()'s largest cost of one call, in :attr:`cost_unit`."""
    lab_max_tick: int = 0
    """The tick of that call."""
    over_budget: int = 0
    """How many calls cost more than :attr:`budget`."""
    cost_unit: int = 1
    """``CRS_COST_INSTRUCTIONS`` (1: WebAssembly instructions) or ``CRS_COST_NS`` (0: native, ns)."""
    budget: int = 0
    """What one lab() call may cost before it counts over the budget, in :attr:`cost_unit`
    (``--budget``'s instructions; natively, the ns they take at the F28335's 150 MHz): the one
    number every report of the budget reads."""
    nan_first_tick: int = -1
    """The first tick lab() returned a NaN or Inf torque (-1: never)."""
    nan_first_joint: int = 0
    """Its joint (``tau1`` .. ``tau3``)."""
    nan_count: int = 0
    """How many such torques in all."""
    printing_runs: int = 0
    """How many times printing() ran."""
    print_triggers: int = 0
    """How many times the lab asked for printing()."""
    safety_flag: int = 0
    """The safety envelope's flag as the run ended."""
    safety_trips: int = 0
    """How many times the arm went outside the safety envelope: from each, the framework's hold
    controller's torques replaced the lab's until the arm was back inside."""
    safety_first_tick: int = -1
    """The tick of the first (-1: never)."""
    safety_ticks: int = 0
    """Ticks outside the envelope in all (the hold's torques applied)."""
    leds: int = 0
    """The LEDs as the run ended (one bit each)."""
    estop_latched: int = 0
    """1 when the emergency stop latched."""
    tx_dropped: int = 0
    """Characters the transmit ring dropped (it was full)."""
    tx_first_drop_tick: int = -1
    """The tick of the first (-1: none)."""
    overflow_tick: int = -1
    """The tick a serial_printf overflowed the board's print buffer (-1: none)."""
    overflow_chars: int = 0
    """How many characters it tried to format."""
    overflow_phase: int = 0
    """Where it was (lab, printing: ``CRS_PHASE_*``)."""
    console_bytes: int = 0
    """Bytes the lab wrote with printf, puts or the like (counted, never shown)."""
    tick: int = 0
    """The next tick to run."""
    first_over_tick: tuple[int, ...] = ()
    """The ticks of the first calls over the budget (up to ``CRS_FIRST_OVER_TICKS`` of them)."""
    native: bool = False
    """The firmware ran natively (its cost is in ns)."""
    motor_board: str = ""
    """The motor board's model (``none``, ``piccolo``)."""
    motor_board_cutouts: int = 0
    """How many times the motor board cut every output."""
    serial_dropped: int = 0
    """Bytes that left the board but never reached the sinks (the crslab process's count)."""
    lab_symbols: int = 0
    """The lab's ``CRS_LAB_HAS_*`` bits."""
    motor_board_events: tuple[tuple[int, int, bool], ...] = ()
    """The motor board's cut-outs and returns: ``(tick, joint, off)``."""

    @classmethod
    def of(cls, fields: dict[str, Any]) -> RunStats:
        """``RunStats(**fields)``, made without ``__init__``'s keywords (a frozen dataclass sets
        each of its 33 fields through ``object.__setattr__``: the worker makes one for every
        chunk's reply, some 400 a second in a server), every field not in ``fields`` its default;
        a name that is no field raises ``TypeError``, as ``__init__`` would.

        >>> RunStats.of({"lab_calls": 3, "native": True}) == RunStats(lab_calls=3, native=True)
        True
        >>> RunStats.of({"lab_cals": 3})
        Traceback (most recent call last):
        ...
        TypeError: RunStats has no field lab_cals
        """
        unknown = fields.keys() - _DEFAULTS.keys()
        if unknown:
            raise TypeError(f"RunStats has no field {', '.join(sorted(unknown))}")
        stats = object.__new__(cls)
        stats.__dict__.update(_DEFAULTS)
        stats.__dict__.update(fields)
        return stats

    def wire(self) -> dict[str, Any]:
        """The statistics as plain data (names to ints, a flag, a name, lists of ticks), every field
        in order (a dataclass's ``__dict__`` holds its fields as ``__init__`` set them: a copy of
        it, not a getattr of each, since a server sends some 400 a second)."""
        plain = dict(self.__dict__)
        plain["first_over_tick"] = list(self.first_over_tick)
        plain["motor_board_events"] = [[t, j, int(off)] for t, j, off in self.motor_board_events]
        return plain

    def row(self) -> tuple:
        """The statistics as a WebAssembly worker sends them (a trusted reply): every field's value
        in order, typed as it is (:meth:`from_row` reads it back). A tenth of :meth:`wire`'s table to
        pickle and unpickle, for some 400 replies a second.

        >>> stats = RunStats(lab_calls=3, first_over_tick=(4100,), motor_board_events=((4600, 1, True),))
        >>> RunStats.from_row(stats.row()) == stats
        True
        """
        return tuple(self.__dict__.values())

    @classmethod
    def from_row(cls, row: tuple) -> RunStats:
        """The statistics :meth:`row` (or a board's :class:`CounterRow`) made, taken as they are."""
        stats = object.__new__(cls)
        stats.__dict__.update(zip(_NAMES, row, strict=True))
        return stats


_NAMES = tuple(f.name for f in dataclasses.fields(RunStats))
"""RunStats's fields in order (read once: every chunk's reply sends them)."""
_DEFAULTS: dict[str, Any] = {f.name: f.default for f in dataclasses.fields(RunStats)}
"""Each field's default, in order (every one a plain value: :meth:`RunStats.of`)."""


class CounterRow:
    """Makes :meth:`RunStats.row` straight from a board's counters (their C names in the order the
    board reports them: :meth:`crslab._bindings.BoardLibrary.counter_values`), with no
    :class:`RunStats` in between: a WebAssembly worker's reply for every chunk.

    >>> make = CounterRow(["lab_calls", "tick"])
    >>> stats = RunStats.from_row(make([7, 250], first_over_tick=(), native=False, motor_board="none"))
    >>> stats == RunStats(lab_calls=7, tick=250, motor_board="none")
    True
    """

    def __init__(self, counters: list[str]) -> None:
        unknown = set(counters) - _DEFAULTS.keys()
        if unknown:
            raise TypeError(f"RunStats has no field {', '.join(sorted(unknown))}")
        self._slots = [_NAMES.index(name) for name in counters]
        self._defaults = list(_DEFAULTS.values())
        self._first_over, self._native, self._board = (_NAMES.index(n) for n in
                                                       ("first_over_tick", "native", "motor_board"))

    def __call__(self, counts: list[int], *, first_over_tick: tuple[int, ...], native: bool,
                 motor_board: str) -> tuple:
        row = self._defaults.copy()
        for slot, value in zip(self._slots, counts):
            row[slot] = value
        row[self._first_over], row[self._native], row[self._board] = first_over_tick, native, motor_board
        return tuple(row)


BOARD_COUNTERS: tuple[str, ...] = tuple(
    itertools.takewhile(lambda name: name != "tick", _NAMES)
)
"""The ``crs_board`` fields the worker reports as they are (whole numbers), by their C names:
:class:`RunStats`'s fields before ``tick``."""

