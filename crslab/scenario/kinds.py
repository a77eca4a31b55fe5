"""Every kind of scenario event (the registry), and turning a file's ``[[event]]`` and ``[plant]`` tables into
events. A new kind is one :class:`crslab.scenario.event.Event` subclass in the ``*_events.py``
module of its group (a new module joins :data:`GROUPS`); its effect on the running arm goes in
:mod:`crslab.sim.event_effects`.

>>> list(EVENT_KINDS)[:4]
['hand', 'release', 'set', 'simulink']
"""

from __future__ import annotations

import numpy as np

from crslab.scenario import expect_events, fault_events, hand_events, lab_events, plant_events
from crslab.scenario.event import Event, RandomFaults, event_kinds, seconds_to_tick
from crslab.scenario.expect_events import Expect
from crslab.scenario.fault_events import DeadMotor, EncoderGlitch, EncoderNoise, StuckEncoder, WristEstop
from crslab.scenario.hand_events import HandMove, HandRelease
from crslab.scenario.lab_events import SetVariable, SimulinkInput
from crslab.scenario.plant_events import EndMass, FrictionScale
from crslab.scenario.table import TableReader, end_mass_kg

__all__ = ["EVENT_KINDS", "DeadMotor", "EncoderGlitch", "EncoderNoise", "EndMass", "Event", "Expect",
           "FrictionScale", "HandMove", "HandRelease", "SetVariable", "SimulinkInput", "StuckEncoder",
           "WristEstop", "parse_event", "parse_plant"]

GROUPS = (hand_events, lab_events, plant_events, fault_events, expect_events)
"""The modules of event kinds, in the order their kinds are listed: the hand, writes to the lab,
the plant, faults, checks."""
_ORDER = [g.__name__ for g in GROUPS]
EVENT_KINDS = dict(sorted(event_kinds().items(), key=lambda kind: _ORDER.index(kind[1].__module__)))
"""Each kind a scenario file may name, and the event class that parses it."""


def parse_event(r: TableReader, faults: RandomFaults) -> list[Event]:
    """The events of one ``[[event]]`` table (one, or several: a move and its release, a fault and
    its end, random glitches)."""
    kind = r.table.get("kind")
    if kind is None:
        raise r.fail("kind", f"missing (one of: {', '.join(EVENT_KINDS)})")
    if kind not in EVENT_KINDS:
        raise r.fail("kind", f"unknown event kind {kind!r} (known: {', '.join(EVENT_KINDS)})")
    at = seconds_to_tick(r.number("at", minimum=0.0))
    return EVENT_KINDS[kind].parse(r, at, r.line_of("kind") or 0, faults)


def parse_plant(r: TableReader) -> tuple[tuple[float, float, float] | None, list[Event]]:
    """The ``[plant]`` table: the true rest pose, and the payload and friction from tick 0."""
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
        events.append(FrictionScale(tick=0, scale=r.number("friction_scale", minimum=0.0),
                                    line=r.line_of("friction_scale") or 0))
    return rest, events
