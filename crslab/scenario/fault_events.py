"""Faults of the encoders, the amplifiers and the wrist e-stop: ``noise``, ``glitch`` (and random
``glitches``), ``stuck_encoder`` and ``dead_motor`` (one class), ``estop``. They act in the C framework
(``crs_faults`` and ``estop_latched`` of csrc/board/board.h)."""

from __future__ import annotations

import random
from dataclasses import dataclass

import numpy as np

from crslab.framework_facts import TICKS_PER_S, WRIST_ESTOP_RAD
from crslab.scenario.event import Event, RandomFaults, seconds_to_tick, until_tick
from crslab.scenario.file_table import joint_numbers, per_joint
from crslab.toml_file import Table

MAX_GLITCHES = 100_000
"""Most glitches one ``glitches`` event may draw."""


def _joints(joints: tuple[int, ...]) -> str:
    return ", ".join(map(str, joints))


@dataclass(frozen=True)
class EncoderNoise(Event):
    """Gaussian encoder noise from now on on ``joints``: standard deviation ``counts[j - 1]`` for
    joint j (0: none); other joints keep theirs. Drawn from a generator seeded with ``rng_state``
    (derived from the scenario's seed; 0 keeps the generator as it is).

    >>> EncoderNoise(tick=0, counts=(0.0, 40.0, 0.0), rng_state=1, joints=(2,)).describe()
    'noise joint 2 std 40 counts'
    """

    counts: tuple[float, float, float]
    rng_state: int
    joints: tuple[int, ...] = (1, 2, 3)
    kinds = ("noise",)

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "counts", "joint", "joints", "until"})
        c = per_joint(r, "counts", whole=False, minimum=0.0)
        counts = (c[0], c[1], c[2])
        joints = (1, 2, 3) if isinstance(r.table["counts"], list) else joint_numbers(r)
        until = until_tick(r, at)
        out: list[Event] = [cls(tick=at, counts=counts, rng_state=faults.next_state(), joints=joints,
                                line=line)]
        if until is not None:  # only these joints go quiet, and the generator runs on
            out.append(cls(tick=until, counts=(0.0, 0.0, 0.0), rng_state=0, joints=joints, line=line))
        return out

    def describe(self) -> str:
        if not any(self.counts):
            return "noise off on joint " + _joints(self.joints)
        return "noise " + ", ".join(f"joint {j} std {self.counts[j - 1]:g}" for j in self.joints) + " counts"


@dataclass(frozen=True)
class EncoderGlitch(Event):
    """For this one tick the encoders read ``counts`` more than the truth (per joint). A
    ``glitches`` table draws many, at random times, from the scenario's seed."""

    counts: tuple[int, int, int]
    kinds = ("glitch", "glitches")

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        if r.table.get("kind") == "glitches":
            return cls._random(r, at, line, faults)
        r.check_keys({"at", "kind", "counts", "joint", "joints"})
        c = per_joint(r, "counts", whole=True)
        return [cls(tick=at, counts=(int(c[0]), int(c[1]), int(c[2])), line=line)]

    @classmethod
    def _random(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
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
        if rate * (until - at) / TICKS_PER_S > MAX_GLITCHES:
            raise r.fail("rate_hz", f"gives more than {MAX_GLITCHES} glitches")
        # Python's random() sequence for an int seed is stable across Python versions
        rng = random.Random(faults.next_state())
        out: list[Event] = []
        t = at / TICKS_PER_S
        while True:
            t += -np.log(1.0 - rng.random()) / rate
            tick = seconds_to_tick(t)
            if tick >= until:
                return out
            joint = joints[int(rng.random() * len(joints))]
            sign = 1 if rng.random() < 0.5 else -1
            counts = (sign * size if joint == 1 else 0, sign * size if joint == 2 else 0,
                      sign * size if joint == 3 else 0)
            out.append(cls(tick=tick, counts=counts, line=line))

    def describe(self) -> str:
        return "glitch " + " ".join(str(c) for c in self.counts) + " counts"


JOINT_FAULTS = {"stuck_encoder": ("stuck", "freed"), "dead_motor": ("dead", "back")}
"""The faults of one joint's hardware, each named as its ``crs_faults`` field (csrc/board/board.h) and
its scenario kind, with the words for on and off: an encoder that freezes at its last reading, an
amplifier that outputs nothing."""


@dataclass(frozen=True)
class JointFault(Event):
    """``fault`` (one of :data:`JOINT_FAULTS`) on ``joints`` from now on (``on`` False ends it).

    >>> JointFault(tick=0, fault="dead_motor", joints=(2, 3), on=False).describe()
    'dead_motor joints 2, 3 back'
    """

    fault: str
    joints: tuple[int, ...]
    on: bool = True
    kinds = tuple(JOINT_FAULTS)

    @property
    def kind(self) -> str:
        return self.fault

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "joint", "joints", "until"})
        fault, joints, until = str(r.table["kind"]), joint_numbers(r), until_tick(r, at)
        out: list[Event] = [cls(tick=at, fault=fault, joints=joints, line=line)]
        if until is not None:
            out.append(cls(tick=until, fault=fault, joints=joints, on=False, line=line))
        return out

    def describe(self) -> str:
        on, off = JOINT_FAULTS[self.fault]
        return f"{self.fault} joints {_joints(self.joints)} {on if self.on else off}"


@dataclass(frozen=True)
class WristEstop(Event):
    """Someone turns the wrist by ``wrist_rad``; past 0.11 rad the framework latches every motor
    output to zero for the rest of the run (the wrist e-stop).

    >>> WristEstop(tick=9000, wrist_rad=0.05).describe()
    'estop: wrist turned 0.05 rad (within 0.11: no e-stop)'
    """

    wrist_rad: float
    kinds = ("estop",)

    @property
    def latches(self) -> bool:
        """True when the turn is past the e-stop's threshold."""
        return abs(self.wrist_rad) > WRIST_ESTOP_RAD

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "wrist_rad"})
        return [cls(tick=at, wrist_rad=r.number("wrist_rad", default=0.2), line=line)]

    def describe(self) -> str:
        if self.latches:
            return f"estop: wrist turned {self.wrist_rad:g} rad: every output latches to zero"
        return f"estop: wrist turned {self.wrist_rad:g} rad (within {WRIST_ESTOP_RAD:g}: no e-stop)"
