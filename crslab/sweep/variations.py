"""What ``crslab sweep --vary NAME=LO:HI`` may vary, and how each value maps onto one run.

This is the one place that knows how a sweep's names reach the plant:

==========================  ========================================================================
``friction``                friction (frictionloss and damping) of every motor, times the identified
``friction1`` .. ``3``      ... of one motor (multiplies with ``friction``)
``payload_kg``              mass carried at the end effector (kg), from tick 0
``mass``                    mass and inertia of every link, times the identified
``rest_offset2`` / ``3``    the arm's true resting motor angle 2 / 3 (rad): where the encoders are
                            zeroed, so the offsets a student measured are a little off
``encoder_noise_counts``    Gaussian encoder noise on every joint, standard deviation in counts
``motor_gain``              joint torque per command unit, times the identified 6 N.m
``var:NAME`` / ``NAME[i]``  the lab's watched variable (or one element), written before tick 0
==========================  ========================================================================

Plant scales go to the run's :class:`crslab.plant.plant_params.PlantParams` (times its own: a
``--plant`` file's arm is varied as crslab's is); the payload, the noise and the variable writes
become scenario events at tick 0, after the scenario's own (so the sweep's
value wins at the start, and the scenario's later events still happen); the resting pose is the
run's. Each sample's noise is drawn from its own seeded generator.

>>> v = parse_vary("friction=0.5:1.5")
>>> v.name, v.low, v.high, v.value_at(0.25)
('friction', 0.5, 1.5, 0.75)
>>> parse_vary("var:Kp[1]=20:60").target
('Kp', 1)
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from crslab.lab.watched import WatchedError, WatchedVar, watched_var
from crslab.scenario.event import Event, rng_state
from crslab.scenario.fault_events import EncoderNoise
from crslab.scenario.lab_events import SetVariable
from crslab.scenario.plant_events import EndMass
from crslab.worker.config import RunConfig

PLANT_NAMES: dict[str, str] = {
    "friction": "friction of every motor, times the identified",
    "friction1": "friction of motor 1, times the identified",
    "friction2": "friction of motor 2, times the identified",
    "friction3": "friction of motor 3, times the identified",
    "payload_kg": "mass carried at the end effector, kg",
    "mass": "mass and inertia of every link, times the identified",
    "rest_offset2": "the arm's true resting motor angle 2, rad",
    "rest_offset3": "the arm's true resting motor angle 3, rad",
    "encoder_noise_counts": "encoder noise on every joint, standard deviation in counts",
    "motor_gain": "joint torque per command unit, times the identified",
}
"""Every name ``--vary`` takes besides ``var:NAME``, and what it is."""
VAR_PREFIX = "var:"
_BOUNDS: dict[str, tuple[float, float]] = {  # (lowest, highest) value each name may take
    "friction": (0.0, math.inf), "friction1": (0.0, math.inf), "friction2": (0.0, math.inf),
    "friction3": (0.0, math.inf), "payload_kg": (0.0, math.inf), "mass": (1e-6, math.inf),
    "rest_offset2": (-math.pi, math.pi), "rest_offset3": (-math.pi, math.pi),
    "encoder_noise_counts": (0.0, math.inf), "motor_gain": (0.0, math.inf),
}
_SPEC = re.compile(r"^\s*([^=\s]+)\s*=\s*([^:]+?)\s*:\s*(.+?)\s*$")
_VAR = re.compile(r"^([A-Za-z_]\w*)(?:\[(\d+)\])?$")
NOISE_ORDINAL = 1 << 40
"""Where the samples' noise generators start among a seed's generator numbers (scenario faults
use the small ones)."""


class VaryError(ValueError):
    """A ``--vary`` that cannot be used: one line naming it and the fix."""


@dataclass(frozen=True)
class Vary:
    """One varied quantity: its column ``name`` (as given), its range, and for ``var:`` the
    watched variable (``target``: name and index) and whether it is an integer (values rounded)."""

    name: str
    low: float
    high: float
    target: tuple[str, int | None] | None = None
    integer: bool = False

    def value_at(self, u: float) -> float:
        """The value at fraction ``u`` (0..1) of the range (rounded for an integer variable)."""
        value = self.low + u * (self.high - self.low)
        return float(round(value)) if self.integer else value


def valid_names(watched: Sequence[WatchedVar]) -> str:
    """The names ``--vary`` takes, for an error message."""
    variables = ", ".join(f"var:{v.name}" + ("[i]" if v.length is not None else "") for v in watched)
    return ", ".join(PLANT_NAMES) + (f", {variables}" if variables else " (the lab watches no variables)")


def parse_vary(text: str) -> Vary:
    """``NAME=LO:HI`` (numbers); raises :class:`VaryError`. Names are checked by :func:`check`.

    >>> parse_vary("mass=1.2:0.8")
    Traceback (most recent call last):
    ...
    crslab.sweep.variations.VaryError: --vary mass=1.2:0.8: LO must not be above HI
    """
    m = _SPEC.match(text)
    if m is None:
        raise VaryError(f"--vary {text}: expected NAME=LO:HI (e.g. friction=0.5:1.5)")
    name = m.group(1)
    try:
        low, high = float(m.group(2)), float(m.group(3))
    except ValueError:
        raise VaryError(f"--vary {text}: LO and HI must be numbers") from None
    if not (math.isfinite(low) and math.isfinite(high)):
        raise VaryError(f"--vary {text}: LO and HI must be finite")
    if low > high:
        raise VaryError(f"--vary {text}: LO must not be above HI")
    target = None
    if name.startswith(VAR_PREFIX):
        v = _VAR.match(name[len(VAR_PREFIX):])
        if v is None:
            raise VaryError(f"--vary {text}: {name} must be var:NAME or var:NAME[i] with a C variable name")
        target = (v.group(1), int(v.group(2)) if v.group(2) is not None else None)
    return Vary(name, low, high, target)


def check(varies: Sequence[Vary], watched: Sequence[WatchedVar], lab_name: str) -> list[Vary]:
    """Check every name against what may vary (the lab's watched variables for ``var:``) and
    every range against what the quantity may take; returns them with integer variables marked.
    Raises :class:`VaryError` (one line listing the valid names for an unknown one)."""
    out, seen = [], set()
    for v in varies:
        if v.name in seen:
            raise VaryError(f"--vary {v.name} is given twice")
        seen.add(v.name)
        if v.target is None:
            if v.name not in PLANT_NAMES:
                raise VaryError(f"--vary {v.name}: unknown name; valid: {valid_names(watched)}")
            lowest, highest = _BOUNDS[v.name]
            if v.low < lowest or v.high > highest:
                raise VaryError(f"--vary {v.name}={v.low:g}:{v.high:g}: {v.name} must be within "
                                f"{lowest:g} .. {highest:g}")
            out.append(v)
            continue
        name, index = v.target
        try:
            var = watched_var(watched, name, index, lab_name)
            var.check_value(v.low, lab_name)
            var.check_value(v.high, lab_name)
        except WatchedError as exc:
            raise VaryError(f"--vary {v.name}: {exc}") from None
        out.append(dataclasses.replace(v, integer=var.is_integer))
    return out


def noise_state(seed: int, sample: int) -> int:
    """The encoder-noise generator state of ``sample`` in a sweep seeded with ``seed``."""
    return rng_state(seed, NOISE_ORDINAL + sample)


def apply(config: RunConfig, varies: Sequence[Vary], values: Sequence[float], *, seed: int,
          sample: int) -> RunConfig:
    """The run of one sample: ``config`` with each of ``varies`` at its value in ``values``.

    >>> from crslab.run.api import make_config
    >>> base = make_config(None, "hands_off")
    >>> run = apply(base, [parse_vary("friction=0:2"), parse_vary("friction2=0:2"),
    ...                    parse_vary("rest_offset3=0:1"), parse_vary("payload_kg=0:2")],
    ...             [0.5, 2.0, 0.3, 1.5], seed=1, sample=0)
    >>> run.plant.friction_scale, run.rest_motor_rad[2], run.scenario.events[-1].describe()
    ((0.5, 1.0, 0.5), 0.3, 'end_mass 1.5 kg')
    """
    friction = [1.0, 1.0, 1.0]
    mass = gain = 1.0
    rest = list(config.rest_motor_rad)
    events: list[Event] = []
    for v, value in zip(varies, values, strict=True):
        name = v.name
        if v.target is not None:
            events.append(SetVariable(tick=0, name=v.target[0], value=float(value), index=v.target[1]))
        elif name == "friction":
            friction = [f * value for f in friction]
        elif name.startswith("friction"):
            friction[int(name[-1]) - 1] *= value
        elif name == "payload_kg":
            events.append(EndMass(tick=0, kg=float(value)))
        elif name == "mass":
            mass = float(value)
        elif name.startswith("rest_offset"):
            rest[int(name[-1]) - 1] = float(value)
        elif name == "encoder_noise_counts":
            c = float(value)
            events.append(EncoderNoise(tick=0, counts=(c, c, c), rng_state=noise_state(seed, sample)))
        elif name == "motor_gain":
            gain = float(value)
        else:  # pragma: no cover - check() lets no other name through
            raise VaryError(f"--vary {name}: unknown name")
    scenario = config.scenario
    if events:  # after the scenario's own tick-0 events (a stable sort): the sweep's value wins
        scenario = dataclasses.replace(scenario, events=tuple(sorted([*scenario.events, *events],
                                                                     key=lambda e: e.tick)))
    base = config.plant
    scales = tuple(b * f for b, f in zip(base.friction_scale, friction))
    plant = dataclasses.replace(base, friction_scale=scales, mass_scale=base.mass_scale * mass,
                                motor_gain=base.motor_gain * gain)
    return dataclasses.replace(config, scenario=scenario, rest_motor_rad=(rest[0], rest[1], rest[2]),
                               plant=plant)


def describe(varies: Sequence[Vary], values: Mapping[str, float] | Sequence[float]) -> str:
    """``friction=0.73, payload_kg=1.2`` for a summary line.

    >>> describe([parse_vary("friction=0:2")], [0.7312])
    'friction=0.7312'
    """
    vals = [values[v.name] for v in varies] if isinstance(values, Mapping) else list(values)
    return ", ".join(f"{v.name}={x:.4g}" for v, x in zip(varies, vals, strict=True))
