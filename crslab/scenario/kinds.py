"""The registry of scenario event kinds: every event class, in one list, and turning a file's
``[[event]]`` table into events of the class its ``kind`` names. A new kind is one
:class:`~crslab.scenario.event.Event` subclass in the ``*_events.py`` module of its group and its
row in :data:`EVENT_CLASSES`; its effect on the running arm goes in
:mod:`crslab.worker.event_effects`.

>>> list(EVENT_KINDS)[:4]
['hand', 'release', 'set', 'simulink']
"""

from __future__ import annotations

from collections.abc import Iterable

from crslab.scenario.event import LONGEST_S, Event, RandomFaults, seconds_to_tick
from crslab.scenario.expect_events import Expect
from crslab.scenario.fault_events import EncoderGlitch, EncoderNoise, JointFault, WristEstop
from crslab.scenario.hand_events import HandMove, HandRelease
from crslab.scenario.lab_events import SetVariable, SimulinkInput
from crslab.scenario.plant_events import EndMass, FrictionScale
from crslab.scenario.push_events import Push
from crslab.toml_file import Table

EVENT_CLASSES: tuple[type[Event], ...] = (
    HandMove, HandRelease,  # the hand
    SetVariable, SimulinkInput,  # writes to the lab
    EndMass, FrictionScale,  # the plant
    Push,  # a force at the end effector
    EncoderNoise, EncoderGlitch, JointFault, WristEstop,  # faults
    Expect,  # checks
)
"""Every class of scenario event, in the order their kinds are listed."""


def kinds_of(classes: Iterable[type[Event]]) -> dict[str, type[Event]]:
    """Each kind the ``classes`` parse, and its class; a kind two of them claim is an error.

    >>> {name: cls.__name__ for name, cls in kinds_of([EncoderGlitch, WristEstop]).items()}
    {'glitch': 'EncoderGlitch', 'glitches': 'EncoderGlitch', 'estop': 'WristEstop'}
    """
    out: dict[str, type[Event]] = {}
    for cls in classes:
        for name in cls.kinds:
            if name in out:
                raise TypeError(f"scenario event kind {name!r} is parsed by {out[name].__name__} and "
                                f"{cls.__name__}")
            out[name] = cls
    return out


EVENT_KINDS = kinds_of(EVENT_CLASSES)
"""Each kind a scenario file may name, and the event class that parses it."""


def parse_event(r: Table, faults: RandomFaults) -> list[Event]:
    """The events of one ``[[event]]`` table (one, or several: a move and its release, a fault and
    its end, random glitches)."""
    kind = r.table.get("kind")
    if kind is None:
        raise r.fail("kind", f"missing (one of: {', '.join(EVENT_KINDS)})")
    if kind not in EVENT_KINDS:
        raise r.fail("kind", f"unknown event kind {kind!r} (known: {', '.join(EVENT_KINDS)})")
    at = seconds_to_tick(r.number("at", minimum=0.0, maximum=LONGEST_S))
    return EVENT_KINDS[kind].parse(r, at, r.line_of("kind") or 0, faults)
