"""Changes to the arm itself: the payload (``end_mass``) and the friction (``friction``); the
``[plant]`` table sets both from tick 0."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from crslab.scenario.event import Event, RandomFaults
from crslab.scenario.file_table import MAX_FRICTION_SCALE, end_mass_kg
from crslab.toml_file import Table


@dataclass(frozen=True)
class EndMass(Event):
    """Carry ``kg`` at the end effector from now on (0 removes it; the course's is 1.54 kg).

    >>> EndMass(tick=0, kg=1.54).describe()
    'end_mass 1.54 kg'
    """

    kg: float
    kinds = ("end_mass",)

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
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
    kinds = ("friction",)

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "scale"})
        return [cls(tick=at, scale=r.number("scale", minimum=0.0, maximum=MAX_FRICTION_SCALE), line=line)]

    def describe(self) -> str:
        return f"friction x{self.scale:g}"


def parse_plant(r: Table) -> tuple[tuple[float, float, float] | None, list[Event]]:
    """The ``[plant]`` table: the arm's true resting pose (rad), and its payload and friction from
    tick 0."""
    r.check_keys({"rest_motor_rad", "rest_motor_deg", "end_mass_kg", "friction_scale"})
    rest = None
    if "rest_motor_rad" in r.table and "rest_motor_deg" in r.table:
        raise r.fail("rest_motor_deg", "give rest_motor_rad or rest_motor_deg, not both")
    for key in ("rest_motor_rad", "rest_motor_deg"):
        if key in r.table:
            v = r.triple(key)
            v = np.radians(v) if key.endswith("deg") else v
            if np.any(np.abs(v) > np.pi):
                raise r.fail(key, "each angle must be within +-180 deg")
            rest = (float(v[0]), float(v[1]), float(v[2]))
    events: list[Event] = []
    if "end_mass_kg" in r.table:
        events.append(EndMass(tick=0, kg=end_mass_kg(r, "end_mass_kg"), line=r.line_of("end_mass_kg") or 0))
    if "friction_scale" in r.table:
        scale = r.number("friction_scale", minimum=0.0, maximum=MAX_FRICTION_SCALE)
        events.append(FrictionScale(tick=0, scale=scale, line=r.line_of("friction_scale") or 0))
    return rest, events
