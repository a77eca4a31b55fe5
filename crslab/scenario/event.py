"""What every scenario event is: a frozen value with the tick it happens at (integer ms) and the
scenario-file ``line`` it came from (0 when made in Python), of one kind.

Each kind of event is one subclass of :class:`Event` (``crslab/scenario/*_events.py``) that holds
all there is to know about it on this side: its name in TOML files (``kind``), how a file's
table becomes events of it (:meth:`Event.parse`) and what it does, in a few words
(:meth:`Event.describe`). What it does to the running arm is the simulator's business: the
worker finds the effect of each event class in :mod:`crslab.worker.event_effects`. Scenarios never
import the simulator.

Times in scenario files are simulated seconds; they are converted once, here, to ticks. Joints
are numbered 1..3 as in the course (``joints`` fields hold those numbers).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar

from crslab.framework_facts import TICKS_PER_S

if TYPE_CHECKING:
    from crslab.toml_file import Table

_MASK64 = (1 << 64) - 1


LONGEST_S = 86_400.0
"""The longest a scenario (or a golden file's recorded run) may last, simulated seconds: a day."""


def seconds_to_tick(seconds: float) -> int:
    """Simulated seconds to the tick (ms) at which something happens, rounded to the nearest.

    >>> seconds_to_tick(4.1)
    4100
    """
    return int(round(seconds * TICKS_PER_S))


def until_tick(r: Table, at: int) -> int | None:
    """The tick of the table's ``until`` (seconds; None without one), which must be after ``at``."""
    if "until" not in r.table:
        return None
    until = seconds_to_tick(r.number("until", minimum=0.0, maximum=LONGEST_S))
    if until <= at:
        raise r.fail("until", "must be later than at")
    return until


def rng_state(seed: int, ordinal: int) -> int:
    """A non-zero 64-bit generator state for the ``ordinal``-th random fault of a scenario
    seeded with ``seed`` (splitmix64 of both).

    >>> rng_state(1, 0) == rng_state(1, 0) != rng_state(2, 0)
    True
    """
    z = (seed * 0x9E3779B97F4A7C15 + (ordinal + 1) * 0xD1B54A32D192ED03) & _MASK64
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & _MASK64
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & _MASK64
    return (z ^ (z >> 31)) or 1


class RandomFaults:
    """Numbers a scenario's random faults in file order, so each gets its own seeded generator:
    a run's faults never depend on how its ticks are chunked."""

    def __init__(self, seed: int) -> None:
        self.seed = seed
        self.count = 0

    def next_state(self) -> int:
        """The generator state of the next random fault."""
        self.count += 1
        return rng_state(self.seed, self.count - 1)


@dataclass(frozen=True)
class Event:
    """One thing that happens at ``tick``. A subclass names the ``kinds`` of ``[[event]]`` table it
    reads and implements :meth:`parse` and :meth:`describe`; its row in
    :data:`crslab.scenario.kinds.EVENT_CLASSES` makes scenario files see it."""

    tick: int
    line: int = field(default=0, compare=False, kw_only=True)
    kinds: ClassVar[tuple[str, ...]] = ()
    """The ``kind`` names of the scenario-file tables :meth:`parse` reads; the first is the event's."""

    @property
    def kind(self) -> str:
        """The event's name in scenario files."""
        return self.kinds[0]

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        """The events one ``[[event]]`` table of this kind gives (at tick ``at``, from ``line``)."""
        raise NotImplementedError

    def describe(self) -> str:
        """What the event does, in a few words (``crslab scenarios FILE`` prints these)."""
        raise NotImplementedError
