"""The hand: someone moves the arm (``hand``) and lets go (``release``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from crslab import crs
from crslab.framework_facts import TICKS_PER_S
from crslab.scenario.event import LONGEST_S, Event, RandomFaults, seconds_to_tick
from crslab.scenario.file_table import hand_target
from crslab.toml_file import Table


@dataclass(frozen=True)
class HandMove(Event):
    """The hand takes the arm to ``target_dh_rad`` over ``duration_ticks`` (a minimum-jerk path)
    and holds it there.

    ``target_dh_rad`` is None for the arm's true resting pose (known only when the run starts).

    Described in the motor angles Lab 1 prints and in DH angles:

    >>> HandMove(tick=5000, target_dh_rad=None, duration_ticks=2000).describe()
    'hand to rest over 2 s (there at t = 7.0 s)'
    >>> HandMove(tick=5000, target_dh_rad=(0.0, -math.pi / 2, math.pi / 2), duration_ticks=2000).describe()
    'hand to motor (0.00, 0.00, 0.00) = DH (0.00, -90.00, 90.00) deg over 2 s (there at t = 7.0 s)'
    """

    target_dh_rad: tuple[float, float, float] | None
    duration_ticks: int
    kinds = ("hand",)

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "motor_deg", "dh_deg", "xyz_in", "pose", "duration", "hold"})
        duration = seconds_to_tick(r.number("duration", default=1.0, minimum=0.0, maximum=LONGEST_S))
        out: list[Event] = [cls(tick=at, target_dh_rad=hand_target(r), duration_ticks=duration, line=line)]
        if "hold" in r.table:
            hold = seconds_to_tick(r.number("hold", minimum=0.0, maximum=LONGEST_S))
            out.append(HandRelease(tick=at + duration + hold, line=line))
        return out

    def describe(self) -> str:
        to = "rest"
        if self.target_dh_rad is not None:
            motor = crs.dh_to_motor(self.target_dh_rad)
            to = f"motor {_degrees(motor)} = DH {_degrees(self.target_dh_rad)} deg"
        there = (self.tick + self.duration_ticks) / TICKS_PER_S
        return f"hand to {to} over {self.duration_ticks / TICKS_PER_S:g} s (there at t = {there:.1f} s)"


def _degrees(angles_rad: object) -> str:
    """``(a, b, c)`` in degrees with two decimals (``-0.00`` shown as ``0.00``)."""
    return "(" + ", ".join(f"{math.degrees(v) + 0.0:.2f}".replace("-0.00", "0.00")
                           for v in angles_rad) + ")"  # type: ignore[attr-defined]


@dataclass(frozen=True)
class HandRelease(Event):
    """The hand lets go of the arm."""

    kinds = ("release",)

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind"})
        return [cls(tick=at, line=line)]

    def describe(self) -> str:
        return "release"
