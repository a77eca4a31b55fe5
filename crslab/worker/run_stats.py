"""A run's statistics, typed: the board's counters the worker reads out of ``crs_sim``
(csrc/board/sim.h) and what the crslab process counts beside them, as one frozen
:class:`RunStats` (``RunResult.stats``), read by attribute.

On the pipe they travel as a table of plain data (:meth:`RunStats.wire`); the crslab process reads
that table back with :meth:`RunStats.read`, which checks every value, since a native lab may have
written it.

>>> stats = RunStats.read({"lab_calls": 900, "first_over_tick": [4100], "native": False})
>>> stats.lab_calls, stats.first_over_tick, stats.nan_first_tick
(900, (4100,), -1)
>>> RunStats.read({"lab_calls": "900"})
Traceback (most recent call last):
...
ValueError: stats['lab_calls'] = '900', not a whole number
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

BOARD_COUNTERS = (
    "lab_calls", "lab_cost_total", "lab_cost_max", "lab_max_tick", "over_budget", "cost_unit", "budget",
    "nan_first_tick", "nan_first_joint", "nan_count", "printing_runs", "print_triggers", "safety_flag",
    "leds", "estop_latched", "tx_dropped", "tx_first_drop_tick", "overflow_tick", "overflow_chars",
    "overflow_phase", "console_bytes",
)
"""The ``crs_sim`` fields the worker reports as they are (whole numbers), by their C names."""


@dataclass(frozen=True)
class RunStats:
    """What a run counted. The board's counters (``crs_sim``'s fields of the same names) first;
    ``tick`` and below are the worker's view of the run; the last three are the crslab process's,
    set once the run has ended."""

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
    """What one lab() call may cost (instructions)."""
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
    """The ticks of the first (up to 8) calls over the budget."""
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

    def wire(self) -> dict[str, Any]:
        """The statistics as plain data (names to ints, a flag, a name, lists of ticks)."""
        return {f.name: _plain(getattr(self, f.name)) for f in dataclasses.fields(self)}

    @classmethod
    def read(cls, raw: Any, what: str = "stats") -> RunStats:
        """Statistics from their plain form, every value checked: raises ``ValueError`` naming
        the first that is not what its field holds (a name crslab does not know included)."""
        if not isinstance(raw, dict):
            raise ValueError(f"{what} is {type(raw).__name__}, not a table")
        values: dict[str, Any] = {}
        for key, value in raw.items():
            kind = _KINDS.get(key) if isinstance(key, str) else None
            if kind is None:
                raise ValueError(f"{what} holds {key!r:.40}, which crslab does not count")
            values[key] = kind(value, f"{what}[{key!r}]")
        return cls(**values)


def _plain(value: object) -> object:
    if isinstance(value, tuple):  # a list of ticks, or of events whose flag travels as 0 or 1
        return [int(v) if isinstance(v, bool) else _plain(v) for v in value]
    return value


def _whole(value: Any, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"{what} = {value!r:.40}, not a whole number")
    return value


def _flag(value: Any, what: str) -> bool:
    if not isinstance(value, bool):
        raise ValueError(f"{what} = {value!r:.40}, not a flag")
    return value


def _name(value: Any, what: str) -> str:
    if not isinstance(value, str):
        raise ValueError(f"{what} = {value!r:.40}, not a name")
    return value


def _ticks(value: Any, what: str) -> tuple[int, ...]:
    if not isinstance(value, list | tuple):
        raise ValueError(f"{what} is {type(value).__name__}, not a list")
    return tuple(_whole(v, f"{what}[...]") for v in value)


def _events(value: Any, what: str) -> tuple[tuple[int, int, bool], ...]:
    if not isinstance(value, list | tuple):
        raise ValueError(f"{what} is {type(value).__name__}, not a list")
    out = []
    for event in value:
        if not isinstance(event, list | tuple) or len(event) != 3:
            raise ValueError(f"{what}[...] is not (tick, joint, off)")
        out.append((_whole(event[0], f"{what}[...]"), _whole(event[1], f"{what}[...]"),
                    bool(_whole(event[2], f"{what}[...]"))))
    return tuple(out)


_KINDS = {
    **{name: _whole for name in BOARD_COUNTERS},
    "tick": _whole, "first_over_tick": _ticks, "native": _flag, "motor_board": _name,
    "motor_board_cutouts": _whole, "serial_dropped": _whole, "lab_symbols": _whole,
    "motor_board_events": _events,
}
"""How each field is read from the pipe."""
