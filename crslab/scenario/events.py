"""The kinds of scenario event. Each is a frozen dataclass with the tick it happens at (integer
ms), a ``kind`` name used in TOML files and the scenario-file ``line`` it came from (0 when made
in Python); the worker applies it between ticks (:func:`crslab.scenario.apply.apply_event`).

Times in scenario files are simulated seconds; they are converted once, here, to ticks. Joints
are numbered 1..3 as in the course (``joints`` fields hold those numbers).

>>> SetVariable(tick=6000, name="whattoprint", value=1.0).kind
'set'
"""

from __future__ import annotations

from dataclasses import dataclass, field

SIMULINK_INPUTS = 7
"""Simulink sends the board seven int16 values (crs-facts 1)."""
INT16_MIN, INT16_MAX = -32768, 32767
WRIST_ESTOP_RAD = 0.11
"""The framework latches every output to zero when the wrist turns more than this (crs-facts 2.7)."""


def seconds_to_tick(seconds: float) -> int:
    """Simulated seconds to the tick (ms) at which something happens, rounded to the nearest.

    >>> seconds_to_tick(4.1)
    4100
    """
    return int(round(seconds * 1000.0))


@dataclass(frozen=True)
class HandMove:
    """The hand takes the arm to ``target_dh_rad`` over ``duration_ticks`` and holds it there.

    ``target_dh_rad`` is None for the arm's true resting pose (known only when the run starts).
    """

    tick: int
    target_dh_rad: tuple[float, float, float] | None
    duration_ticks: int
    kind: str = "hand"
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class HandRelease:
    """The hand lets go of the arm."""

    tick: int
    kind: str = "release"
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class SetVariable:
    """Write ``value`` to the lab's watched variable ``name`` (element ``index`` of an array), as
    the course's ``ME446_serialwrite`` does while the DSP runs. Integer variables get the value
    rounded."""

    tick: int
    name: str
    value: float
    index: int | None = None
    kind: str = "set"
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class SimulinkInput:
    """Simulink sends values down: ``values`` holds ``(input, value)`` pairs, input 1..7, value an
    int16. The lab sees them in ``int SIMU_Var1_fromSIMU_16bit`` .. ``SIMU_Var7_fromSIMU_16bit``
    (declared ``extern`` in the lab file); inputs not named keep their value."""

    tick: int
    values: tuple[tuple[int, int], ...]
    kind: str = "simulink"
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class EndMass:
    """Carry ``kg`` at the end effector from now on (0 removes it; the course's is 1.54 kg)."""

    tick: int
    kg: float
    kind: str = "end_mass"
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class FrictionScale:
    """Scale the model's friction (frictionloss and damping of every joint and of the forearm
    tendon) to ``scale`` times the identified values (absolute, not cumulative)."""

    tick: int
    scale: float
    kind: str = "friction"
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class EncoderNoise:
    """Gaussian encoder noise from now on on ``joints``: standard deviation ``counts[j - 1]`` for
    joint j (0: none); other joints keep theirs. Drawn from a generator seeded with ``rng_state``
    (derived from the scenario's seed; 0 keeps the generator as it is)."""

    tick: int
    counts: tuple[float, float, float]
    rng_state: int
    joints: tuple[int, ...] = (1, 2, 3)
    kind: str = "noise"
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class EncoderGlitch:
    """For this one tick the encoders read ``counts`` more than the truth (per joint)."""

    tick: int
    counts: tuple[int, int, int]
    kind: str = "glitch"
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class StuckEncoder:
    """The encoders of ``joints`` freeze at their last reading (``stuck`` False frees them)."""

    tick: int
    joints: tuple[int, ...]
    stuck: bool = True
    kind: str = "stuck_encoder"
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class DeadMotor:
    """The amplifiers of ``joints`` output nothing (``dead`` False brings them back)."""

    tick: int
    joints: tuple[int, ...]
    dead: bool = True
    kind: str = "dead_motor"
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class WristEstop:
    """Someone turns the wrist by ``wrist_rad``; past 0.11 rad the framework latches every motor
    output to zero for the rest of the run (the wrist e-stop)."""

    tick: int
    wrist_rad: float
    kind: str = "estop"
    line: int = field(default=0, compare=False)


Event = (HandMove | HandRelease | SetVariable | SimulinkInput | EndMass | FrictionScale | EncoderNoise
         | EncoderGlitch | StuckEncoder | DeadMotor | WristEstop)


def describe(event: Event) -> str:
    """What an event does, in a few words (``crslab scenarios FILE`` prints these).

    >>> describe(SetVariable(tick=5000, name="table", value=-7.0, index=2))
    'set table[2] = -7'
    >>> describe(WristEstop(tick=9000, wrist_rad=0.05))
    'estop: wrist turned 0.05 rad (within 0.11: no e-stop)'
    """
    import math

    e = event
    if isinstance(e, HandMove):
        to = "rest" if e.target_dh_rad is None else (
            "DH (" + ", ".join(f"{math.degrees(v):.2f}" for v in e.target_dh_rad) + ") deg")
        return f"hand to {to} over {e.duration_ticks / 1000:g} s"
    if isinstance(e, HandRelease):
        return "release"
    if isinstance(e, SetVariable):
        where = e.name if e.index is None else f"{e.name}[{e.index}]"
        return f"set {where} = {e.value:g}"
    if isinstance(e, SimulinkInput):
        return "simulink " + ", ".join(f"input {i} = {v}" for i, v in e.values)
    if isinstance(e, EndMass):
        return f"end_mass {e.kg:g} kg"
    if isinstance(e, FrictionScale):
        return f"friction x{e.scale:g}"
    if isinstance(e, EncoderNoise):
        if not any(e.counts):
            return "noise off on joint " + ", ".join(map(str, e.joints))
        return "noise " + ", ".join(f"joint {j} std {e.counts[j - 1]:g}" for j in e.joints) + " counts"
    if isinstance(e, EncoderGlitch):
        return "glitch " + " ".join(str(c) for c in e.counts) + " counts"
    if isinstance(e, StuckEncoder):
        return f"stuck_encoder joints {', '.join(map(str, e.joints))} {'stuck' if e.stuck else 'freed'}"
    if isinstance(e, DeadMotor):
        return f"dead_motor joints {', '.join(map(str, e.joints))} {'dead' if e.dead else 'back'}"
    if abs(e.wrist_rad) > WRIST_ESTOP_RAD:
        return f"estop: wrist turned {e.wrist_rad:g} rad: every output latches to zero"
    return f"estop: wrist turned {e.wrist_rad:g} rad (within {WRIST_ESTOP_RAD:g}: no e-stop)"
