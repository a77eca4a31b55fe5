"""Changes to the arm itself: the payload (``end_mass``) and the friction (``friction``); the
``[plant]`` table sets both from tick 0."""

from __future__ import annotations

from dataclasses import dataclass

from crslab.scenario.event import Event, RandomFaults
from crslab.scenario.table import TableReader, end_mass_kg


@dataclass(frozen=True)
class EndMass(Event):
    """Carry ``kg`` at the end effector from now on (0 removes it; the course's is 1.54 kg).

    >>> EndMass(tick=0, kg=1.54).describe()
    'end_mass 1.54 kg'
    """

    kg: float
    kind = "end_mass"

    @classmethod
    def parse(cls, r: TableReader, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "kg"})
        if "kg" not in r.table:
            raise r.fail("kg", "missing (a number of kg, or \"course\")")
        return [cls(tick=at, kg=end_mass_kg(r, "kg"), line=line)]

    def describe(self) -> str:
        return f"end_mass {self.kg:g} kg"


@dataclass(frozen=True)
class FrictionScale(Event):
    """Scale the arm's friction (dry and viscous, every motor) to ``scale`` times the run's plant
    (crslab's identified values, or the ``--plant`` file's): absolute, not cumulative."""

    scale: float
    kind = "friction"

    @classmethod
    def parse(cls, r: TableReader, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "scale"})
        return [cls(tick=at, scale=r.number("scale", minimum=0.0), line=line)]

    def describe(self) -> str:
        return f"friction x{self.scale:g}"
