"""Turning the ``[[event]]`` and ``[plant]`` tables of a scenario into events (one method per
event kind), numbering the random faults so each gets its own seeded generator."""

from __future__ import annotations

import random
import re

import numpy as np

from crslab.scenario.events import (
    INT16_MAX,
    INT16_MIN,
    SIMULINK_INPUTS,
    DeadMotor,
    EncoderGlitch,
    EncoderNoise,
    EndMass,
    Event,
    FrictionScale,
    HandMove,
    HandRelease,
    SetVariable,
    SimulinkInput,
    StuckEncoder,
    WristEstop,
    seconds_to_tick,
)
from crslab.scenario.table import TableReader, end_mass_kg, hand_target, joint_numbers, per_joint, until_tick

MAX_GLITCHES = 100_000  # per glitches event
EVENT_KINDS = ("hand", "release", "set", "simulink", "end_mass", "friction", "noise", "glitch", "glitches",
               "stuck_encoder", "dead_motor", "estop")
_MASK64 = (1 << 64) - 1
_IDENTIFIER = re.compile(r"[A-Za-z_]\w*\Z")


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


class EventParser:
    """Turns the ``[[event]]`` tables into events, numbering the random ones for their seeds."""

    def __init__(self, seed: int) -> None:
        self.seed = seed
        self.random_faults = 0

    def _next_state(self) -> int:
        self.random_faults += 1
        return rng_state(self.seed, self.random_faults - 1)

    def parse(self, r: TableReader) -> list[Event]:
        kind = r.table.get("kind")
        if kind is None:
            raise r.fail("kind", f"missing (one of: {', '.join(EVENT_KINDS)})")
        if kind not in EVENT_KINDS:
            raise r.fail("kind", f"unknown event kind {kind!r} (known: {', '.join(EVENT_KINDS)})")
        at = seconds_to_tick(r.number("at", minimum=0.0))
        line = r.line_of("kind") or 0
        return getattr(self, f"_{kind}")(r, at, line)

    def _hand(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "motor_deg", "dh_deg", "xyz_in", "pose", "duration", "hold"})
        duration = seconds_to_tick(r.number("duration", default=1.0, minimum=0.0))
        target = hand_target(r)
        out: list[Event] = [HandMove(tick=at, target_dh_rad=target, duration_ticks=duration, line=line)]
        if "hold" in r.table:
            hold = seconds_to_tick(r.number("hold", minimum=0.0))
            out.append(HandRelease(tick=at + duration + hold, line=line))
        return out

    def _release(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind"})
        return [HandRelease(tick=at, line=line)]

    def _set(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "var", "value", "index"})
        name = r.text("var")
        if not _IDENTIFIER.match(name):
            raise r.fail("var", f"must be a C variable name, got {name!r}")
        index = r.integer("index", minimum=0) if "index" in r.table else None
        line = r.line_of("var") or line  # what check_lab's errors point at
        return [SetVariable(tick=at, name=name, value=r.number("value"), index=index, line=line)]

    def _simulink(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "values", "input", "value"})
        if "values" in r.table:
            if "input" in r.table or "value" in r.table:
                raise r.fail("values", "give values, or input and value, not both")
            values = r.table["values"]
            if (not isinstance(values, list) or not 1 <= len(values) <= SIMULINK_INPUTS
                    or not all(isinstance(v, int) and not isinstance(v, bool) and INT16_MIN <= v <= INT16_MAX
                               for v in values)):
                raise r.fail("values", f"must be a list of 1 to {SIMULINK_INPUTS} whole numbers from "
                             f"{INT16_MIN} to {INT16_MAX} (int16), got {values!r}")
            pairs = tuple((i + 1, v) for i, v in enumerate(values))
        else:
            pairs = ((r.integer("input", minimum=1, maximum=SIMULINK_INPUTS),
                      r.integer("value", minimum=INT16_MIN, maximum=INT16_MAX)),)
        return [SimulinkInput(tick=at, values=pairs, line=line)]

    def _end_mass(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "kg"})
        if "kg" not in r.table:
            raise r.fail("kg", "missing (a number of kg, or \"course\")")
        return [EndMass(tick=at, kg=end_mass_kg(r, "kg"), line=line)]

    def _friction(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "scale"})
        return [FrictionScale(tick=at, scale=r.number("scale", minimum=0.0), line=line)]

    def _noise(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "counts", "joint", "joints", "until"})
        counts = per_joint(r, "counts", whole=False, minimum=0.0)
        joints = (1, 2, 3) if isinstance(r.table["counts"], list) else joint_numbers(r)
        until = until_tick(r, at)
        out: list[Event] = [EncoderNoise(tick=at, counts=counts, rng_state=self._next_state(),
                                         joints=joints, line=line)]
        if until is not None:  # only these joints go quiet, and the generator runs on
            out.append(EncoderNoise(tick=until, counts=(0.0, 0.0, 0.0), rng_state=0, joints=joints,
                                    line=line))
        return out

    def _glitch(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "counts", "joint", "joints"})
        counts = tuple(int(v) for v in per_joint(r, "counts", whole=True))
        return [EncoderGlitch(tick=at, counts=counts, line=line)]

    def _glitches(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "until", "rate_hz", "counts", "joint", "joints"})
        if "until" not in r.table:
            raise r.fail("until", "missing (random glitches need an end)")
        until = until_tick(r, at)
        assert until is not None
        rate = r.number("rate_hz", minimum=0.0)
        if rate <= 0:
            raise r.fail("rate_hz", "must be more than 0")
        size = r.integer("counts", minimum=1, maximum=2**31 - 1)
        joints = joint_numbers(r)
        if rate * (until - at) / 1000.0 > MAX_GLITCHES:
            raise r.fail("rate_hz", f"gives more than {MAX_GLITCHES} glitches")
        # Python's random() sequence for an int seed is stable across Python versions
        rng = random.Random(self._next_state())
        out: list[Event] = []
        t = at / 1000.0
        while True:
            t += -np.log(1.0 - rng.random()) / rate
            tick = seconds_to_tick(t)
            if tick >= until:
                return out
            joint = joints[int(rng.random() * len(joints))]
            sign = 1 if rng.random() < 0.5 else -1
            counts = tuple(sign * size if j == joint else 0 for j in (1, 2, 3))
            out.append(EncoderGlitch(tick=tick, counts=counts, line=line))

    def _stuck_encoder(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "joint", "joints", "until"})
        joints, until = joint_numbers(r), until_tick(r, at)
        out: list[Event] = [StuckEncoder(tick=at, joints=joints, line=line)]
        if until is not None:
            out.append(StuckEncoder(tick=until, joints=joints, stuck=False, line=line))
        return out

    def _dead_motor(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "joint", "joints", "until"})
        joints, until = joint_numbers(r), until_tick(r, at)
        out: list[Event] = [DeadMotor(tick=at, joints=joints, line=line)]
        if until is not None:
            out.append(DeadMotor(tick=until, joints=joints, dead=False, line=line))
        return out

    def _estop(self, r: TableReader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "wrist_rad"})
        return [WristEstop(tick=at, wrist_rad=r.number("wrist_rad", default=0.2), line=line)]


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
