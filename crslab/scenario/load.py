"""Read a scenario from TOML (a built-in name or a file) into a :class:`Scenario`.

The format, with every event kind (docs/scenarios.md explains each one further)::

    name = "example"
    description = "one line shown by `crslab scenarios`"
    end = 20.0                      # simulated seconds; the run ends here
    seed = 7                        # seeds the random faults (noise, glitches); default 1

    [plant]                         # the arm as it is at power-up (all keys optional)
    rest_motor_rad = [0, -0.40, 0.26]   # true resting pose the encoders are zeroed in (or rest_motor_deg)
    end_mass_kg = "course"          # the course's added end mass (1.54 kg), or a number of kg
    friction_scale = 1.0            # times the identified friction

    [[event]]
    at = 5.0                        # simulated seconds
    kind = "hand"                   # move the arm by hand, then hold it there
    motor_deg = [0, 0, 0]           # or dh_deg, xyz_in (elbow-up IK), or pose = "rest"
    duration = 2.0                  # seconds to get there (default 1)
    hold = 2.0                      # optional: let go this long after arriving

    [[event]]
    at = 9.0
    kind = "release"                # let go

    [[event]]
    at = 6.0
    kind = "set"                    # write a watched (#pragma DATA_SECTION) variable
    var = "whattoprint"
    value = 1
    # index = 3                     # an element of a watched array

    [[event]]
    at = 6.0
    kind = "simulink"               # Simulink sends int16 values down
    values = [100, -20]             # inputs 1, 2, ... (or input = 3, value = 5)

    [[event]]
    at = 10.0
    kind = "end_mass"               # the payload changes
    kg = "course"                   # or a number; 0 removes it

    [[event]]
    at = 10.0
    kind = "friction"
    scale = 0.5

    [[event]]
    at = 7.0
    kind = "noise"                  # encoder noise, standard deviation in counts
    counts = 40                     # or one value per joint: [40, 0, 10]
    joints = [2, 3]                 # optional (joint = 2 for one); default all three
    until = 9.0                     # optional: the fault clears then

    [[event]]
    at = 7.5
    kind = "glitch"                 # one tick where the encoders jump
    joint = 2
    counts = 5000

    [[event]]
    at = 8.0
    kind = "glitches"               # random glitches (seeded)
    until = 12.0
    rate_hz = 2.0                   # on average per second
    counts = 3000                   # size; the sign and the joint (of joints) are random

    [[event]]
    at = 11.0
    kind = "stuck_encoder"          # the reading freezes
    joint = 1
    until = 12.0                    # optional

    [[event]]
    at = 13.0
    kind = "dead_motor"             # the amplifier outputs nothing
    joint = 3
    until = 14.0                    # optional

    [[event]]
    at = 15.0
    kind = "estop"                  # the wrist is turned: past 0.11 rad the outputs latch to zero
    wrist_rad = 0.2                 # optional, default 0.2

Every error names the file, the line and the key, and nothing runs.
"""

from __future__ import annotations

import random
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from crslab import crs
from crslab.lab.build import LabBuild
from crslab.plant.params import COURSE_END_MASS_KG
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

BUILTIN_DIR = Path(__file__).resolve().parents[1] / "scenarios"
DEFAULT_SCENARIO = "tour"
DEFAULT_SEED = 1
MAX_GLITCHES = 100_000  # per glitches event
EVENT_KINDS = ("hand", "release", "set", "simulink", "end_mass", "friction", "noise", "glitch", "glitches",
               "stuck_encoder", "dead_motor", "estop")
_MASK64 = (1 << 64) - 1
_IDENTIFIER = re.compile(r"[A-Za-z_]\w*\Z")
_HEADER = re.compile(r"^\s*\[")


class ScenarioError(ValueError):
    """A scenario that cannot be used; the message names file, line and key."""


@dataclass(frozen=True)
class Scenario:
    """A named timeline of events ending at ``end_tick``.

    ``rest_motor_rad`` is the arm's true resting pose when the scenario sets it (None: the
    default); ``seed`` is what the random faults were drawn from.
    """

    name: str
    description: str
    end_tick: int
    events: tuple[Event, ...] = field(default_factory=tuple)
    source: str = ""
    seed: int = DEFAULT_SEED
    rest_motor_rad: tuple[float, float, float] | None = None


def builtin_names() -> list[str]:
    """Names of the scenarios that ship with crslab."""
    return sorted(p.stem for p in BUILTIN_DIR.glob("*.toml"))


def resolve(name_or_path: str | None) -> Path:
    """A built-in scenario's file, or the given path."""
    if name_or_path is None:
        name_or_path = DEFAULT_SCENARIO
    builtin = BUILTIN_DIR / f"{name_or_path}.toml"
    if builtin.is_file():
        return builtin
    path = Path(name_or_path)
    if not path.is_file():
        raise ScenarioError(
            f"{name_or_path}: no such scenario file or built-in (built-ins: {', '.join(builtin_names())})"
        )
    return path


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


class _Reader:
    """One TOML table (the top level, ``[plant]`` or one ``[[event]]``) and where it sits."""

    def __init__(self, path: Path, table: dict, lines: list[str], header: int | None) -> None:
        self.path, self.table, self.lines, self.header = path, table, lines, header

    def line_of(self, key: str) -> int | None:
        """1-based line where ``key`` is set in this table (else its header's line)."""
        if self.header is None and not self.lines:
            return None
        start = 0 if self.header is None else self.header
        pattern = re.compile(rf'^\s*"?{re.escape(key)}"?\s*=')
        for i in range(start, len(self.lines)):
            if i > start and _HEADER.match(self.lines[i]):
                break
            if pattern.match(self.lines[i]):
                return i + 1
        return self.header + 1 if self.header is not None else None

    def fail(self, key: str, why: str) -> ScenarioError:
        line = self.line_of(key.split("|")[0])
        where = f"{self.path}:{line}" if line else str(self.path)
        return ScenarioError(f"{where}: {key}: {why}")

    def has(self, key: str) -> bool:
        return key in self.table

    def number(self, key: str, *, default: float | None = None, minimum: float | None = None,
               maximum: float | None = None) -> float:
        if key not in self.table:
            if default is None:
                raise self.fail(key, "missing")
            return default
        value = self.table[key]
        if isinstance(value, bool) or not isinstance(value, int | float) or not np.isfinite(value):
            raise self.fail(key, f"must be a number, got {value!r}")
        if minimum is not None and value < minimum:
            raise self.fail(key, f"must be at least {minimum:g}, got {value!r}")
        if maximum is not None and value > maximum:
            raise self.fail(key, f"must be at most {maximum:g}, got {value!r}")
        return float(value)

    def integer(self, key: str, *, minimum: int | None = None, maximum: int | None = None) -> int:
        value = self.table.get(key)
        if value is None:
            raise self.fail(key, "missing")
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.fail(key, f"must be a whole number, got {value!r}")
        if (minimum is not None and value < minimum) or (maximum is not None and value > maximum):
            raise self.fail(key, f"must be from {minimum} to {maximum}, got {value!r}")
        return value

    def text(self, key: str) -> str:
        value = self.table.get(key)
        if value is None:
            raise self.fail(key, "missing")
        if not isinstance(value, str):
            raise self.fail(key, f"must be a string, got {value!r}")
        return value

    def triple(self, key: str) -> np.ndarray:
        value = self.table[key]
        if (not isinstance(value, list) or len(value) != 3
                or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)):
            raise self.fail(key, f"must be a list of three numbers, got {value!r}")
        return np.asarray(value, dtype=float)

    def check_keys(self, allowed: set[str]) -> None:
        for key in self.table:
            if key not in allowed:
                raise self.fail(key, f"unknown key (allowed: {', '.join(sorted(allowed))})")


def _hand_target(r: _Reader) -> tuple[float, float, float] | None:
    given = [k for k in ("motor_deg", "dh_deg", "xyz_in", "pose") if k in r.table]
    if len(given) != 1:
        raise r.fail("motor_deg|dh_deg|xyz_in|pose", "give exactly one target")
    key = given[0]
    if key == "pose":
        if r.table[key] != "rest":
            raise r.fail(key, f"the only named pose is \"rest\", got {r.table[key]!r}")
        return None
    v = r.triple(key)
    if key == "dh_deg":
        dh = np.radians(v)
    elif key == "motor_deg":
        dh = crs.motor_to_dh(np.radians(v))
    else:
        q, status = crs.ik_with_status(v, elbow="up")
        if int(status) != crs.IK_OK:
            raise r.fail(key, f"target {v.tolist()} in is {crs.IK_STATUS_TEXT[int(status)]}")
        dh = crs.motor_to_dh(q)
    return (float(dh[0]), float(dh[1]), float(dh[2]))


def _joints(r: _Reader) -> tuple[int, ...]:
    """``joint = N`` or ``joints = [..]`` (numbers 1..3); all three when neither is given."""
    if "joint" in r.table and "joints" in r.table:
        raise r.fail("joints", "give joint or joints, not both")
    if "joint" in r.table:
        return (r.integer("joint", minimum=1, maximum=3),)
    if "joints" not in r.table:
        return (1, 2, 3)
    value = r.table["joints"]
    if (not isinstance(value, list) or not value
            or not all(isinstance(j, int) and not isinstance(j, bool) and 1 <= j <= 3 for j in value)):
        raise r.fail("joints", f"must be a list of joint numbers 1..3, got {value!r}")
    return tuple(sorted(set(value)))


def _per_joint(r: _Reader, key: str, *, whole: bool, minimum: float | None = None) -> tuple[float, ...]:
    """``key`` as three values: a list of three, or one number for ``joint``/``joints``."""
    if key not in r.table:
        raise r.fail(key, "missing")
    value = r.table[key]
    if isinstance(value, list):
        if "joint" in r.table or "joints" in r.table:
            raise r.fail(key, "a list gives every joint its value: leave out joint/joints")
        values = list(r.triple(key))
        raw = value
    else:
        r.number(key, minimum=minimum)
        joints = _joints(r)
        values = [float(value) if j + 1 in joints else 0.0 for j in range(3)]
        raw = [value]
    if whole and not all(isinstance(v, int) for v in raw):
        raise r.fail(key, f"must be whole numbers of counts, got {value!r}")
    if minimum is not None and any(v < minimum for v in values):
        raise r.fail(key, f"must be at least {minimum:g}, got {value!r}")
    return tuple(values)


def _until(r: _Reader, at: int) -> int | None:
    if "until" not in r.table:
        return None
    until = seconds_to_tick(r.number("until", minimum=0.0))
    if until <= at:
        raise r.fail("until", "must be later than at")
    return until


def _end_mass(r: _Reader, key: str) -> float:
    value = r.table.get(key)
    if value == "course":
        return COURSE_END_MASS_KG
    if isinstance(value, str):
        raise r.fail(key, f"must be a number of kg or \"course\", got {value!r}")
    return r.number(key, minimum=0.0)


class _Parser:
    """Turns the ``[[event]]`` tables into events, numbering the random ones for their seeds."""

    def __init__(self, seed: int) -> None:
        self.seed = seed
        self.random_faults = 0

    def _next_state(self) -> int:
        self.random_faults += 1
        return rng_state(self.seed, self.random_faults - 1)

    def parse(self, r: _Reader) -> list[Event]:
        kind = r.table.get("kind")
        if kind is None:
            raise r.fail("kind", f"missing (one of: {', '.join(EVENT_KINDS)})")
        if kind not in EVENT_KINDS:
            raise r.fail("kind", f"unknown event kind {kind!r} (known: {', '.join(EVENT_KINDS)})")
        at = seconds_to_tick(r.number("at", minimum=0.0))
        line = r.line_of("kind") or 0
        return getattr(self, f"_{kind}")(r, at, line)

    def _hand(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "motor_deg", "dh_deg", "xyz_in", "pose", "duration", "hold"})
        duration = seconds_to_tick(r.number("duration", default=1.0, minimum=0.0))
        target = _hand_target(r)
        out: list[Event] = [HandMove(tick=at, target_dh_rad=target, duration_ticks=duration, line=line)]
        if "hold" in r.table:
            hold = seconds_to_tick(r.number("hold", minimum=0.0))
            out.append(HandRelease(tick=at + duration + hold, line=line))
        return out

    def _release(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind"})
        return [HandRelease(tick=at, line=line)]

    def _set(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "var", "value", "index"})
        name = r.text("var")
        if not _IDENTIFIER.match(name):
            raise r.fail("var", f"must be a C variable name, got {name!r}")
        index = r.integer("index", minimum=0) if "index" in r.table else None
        line = r.line_of("var") or line  # what check_lab's errors point at
        return [SetVariable(tick=at, name=name, value=r.number("value"), index=index, line=line)]

    def _simulink(self, r: _Reader, at: int, line: int) -> list[Event]:
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

    def _end_mass(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "kg"})
        if "kg" not in r.table:
            raise r.fail("kg", "missing (a number of kg, or \"course\")")
        return [EndMass(tick=at, kg=_end_mass(r, "kg"), line=line)]

    def _friction(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "scale"})
        return [FrictionScale(tick=at, scale=r.number("scale", minimum=0.0), line=line)]

    def _noise(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "counts", "joint", "joints", "until"})
        counts = _per_joint(r, "counts", whole=False, minimum=0.0)
        joints = (1, 2, 3) if isinstance(r.table["counts"], list) else _joints(r)
        until = _until(r, at)
        out: list[Event] = [EncoderNoise(tick=at, counts=counts, rng_state=self._next_state(),
                                         joints=joints, line=line)]
        if until is not None:  # only these joints go quiet, and the generator runs on
            out.append(EncoderNoise(tick=until, counts=(0.0, 0.0, 0.0), rng_state=0, joints=joints,
                                    line=line))
        return out

    def _glitch(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "counts", "joint", "joints"})
        counts = tuple(int(v) for v in _per_joint(r, "counts", whole=True))
        return [EncoderGlitch(tick=at, counts=counts, line=line)]

    def _glitches(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "until", "rate_hz", "counts", "joint", "joints"})
        if "until" not in r.table:
            raise r.fail("until", "missing (random glitches need an end)")
        until = _until(r, at)
        assert until is not None
        rate = r.number("rate_hz", minimum=0.0)
        if rate <= 0:
            raise r.fail("rate_hz", "must be more than 0")
        size = r.integer("counts", minimum=1, maximum=2**31 - 1)
        joints = _joints(r)
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

    def _stuck_encoder(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "joint", "joints", "until"})
        joints, until = _joints(r), _until(r, at)
        out: list[Event] = [StuckEncoder(tick=at, joints=joints, line=line)]
        if until is not None:
            out.append(StuckEncoder(tick=until, joints=joints, stuck=False, line=line))
        return out

    def _dead_motor(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "joint", "joints", "until"})
        joints, until = _joints(r), _until(r, at)
        out: list[Event] = [DeadMotor(tick=at, joints=joints, line=line)]
        if until is not None:
            out.append(DeadMotor(tick=until, joints=joints, dead=False, line=line))
        return out

    def _estop(self, r: _Reader, at: int, line: int) -> list[Event]:
        r.check_keys({"at", "kind", "wrist_rad"})
        return [WristEstop(tick=at, wrist_rad=r.number("wrist_rad", default=0.2), line=line)]


def _plant(r: _Reader) -> tuple[tuple[float, float, float] | None, list[Event]]:
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
        events.append(EndMass(tick=0, kg=_end_mass(r, "end_mass_kg"), line=r.line_of("end_mass_kg") or 0))
    if "friction_scale" in r.table:
        events.append(FrictionScale(tick=0, scale=r.number("friction_scale", minimum=0.0),
                                    line=r.line_of("friction_scale") or 0))
    return rest, events


def _header_lines(lines: list[str], name: str) -> list[int]:
    """0-based indexes of each ``[[name]]`` (or ``[name]``) header, in order."""
    pattern = re.compile(rf"^\s*\[\[?\s*{re.escape(name)}\s*\]\]?\s*(#.*)?$")
    return [i for i, line in enumerate(lines) if pattern.match(line)]


def parse_scenario(text: str, path: Path) -> Scenario:
    """Check and parse scenario ``text`` read from ``path`` (named in errors).

    >>> parse_scenario('end = 2.0\\n[[event]]\\nat = 1\\nkind = "estop"\\n', Path("x.toml")).events
    (WristEstop(tick=1000, wrist_rad=0.2, kind='estop', line=4),)
    >>> parse_scenario('end = 2.0\\n[[event]]\\nat = 1\\nkind = "nap"\\n', Path("x.toml"))
    Traceback (most recent call last):
    ...
    crslab.scenario.load.ScenarioError: x.toml:4: kind: unknown event kind 'nap' (known: ...)
    """
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"\(at line (\d+)", str(exc))
        where = f"{path}:{m.group(1)}" if m else str(path)
        raise ScenarioError(f"{where}: not valid TOML: {exc}") from None
    lines = text.splitlines()
    top = _Reader(path, doc, lines, None)
    top.check_keys({"name", "description", "end", "seed", "plant", "event"})
    for key in ("name", "description"):
        if key in doc:
            top.text(key)
    seed = top.integer("seed", minimum=0, maximum=2**63 - 1) if "seed" in doc else DEFAULT_SEED
    end_tick = seconds_to_tick(top.number("end", minimum=0.001))
    rest, events = None, []
    if "plant" in doc:
        if not isinstance(doc["plant"], dict):
            raise top.fail("plant", "must be a table ([plant])")
        plant_at = _header_lines(lines, "plant")
        rest, events = _plant(_Reader(path, doc["plant"], lines, plant_at[0] if plant_at else None))
    raw_events = doc.get("event", [])
    if not isinstance(raw_events, list):
        raise top.fail("event", "must be an array of tables ([[event]])")
    headers = _header_lines(lines, "event")
    parser = _Parser(seed)
    for i, table in enumerate(raw_events):
        if not isinstance(table, dict):
            raise top.fail("event", "must be an array of tables ([[event]])")
        r = _Reader(path, table, lines, headers[i] if i < len(headers) else None)
        parsed = parser.parse(r)
        if parsed and parsed[0].tick > end_tick:
            raise r.fail("at", f"{parsed[0].tick / 1000:g} s is after the end ({end_tick / 1000:g} s)")
        events.extend(parsed)
    events.sort(key=lambda e: e.tick)  # stable: events at the same tick keep their file order
    return Scenario(
        name=str(doc.get("name", path.stem)),
        description=str(doc.get("description", "")),
        end_tick=end_tick,
        events=tuple(events),
        source=str(path),
        seed=seed,
        rest_motor_rad=rest,
    )


def load_scenario(name_or_path: str | None = None) -> Scenario:
    """Load and check a scenario; raises :class:`ScenarioError` naming file, line and key.

    >>> s = load_scenario("tour")
    >>> s.name, s.end_tick > 0, s.events[0].kind
    ('tour', True, 'hand')
    """
    path = resolve(name_or_path)
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"{path}: cannot be read ({getattr(exc, 'strerror', None) or exc})") from None
    return parse_scenario(text, path)


def check_lab(scenario: Scenario, build: LabBuild) -> None:
    """Check that every variable the scenario writes is one the lab watches (``#pragma
    DATA_SECTION``), with an index exactly when it is an array; raises :class:`ScenarioError`."""
    watched = {v.name: v for v in build.watched}
    lab = build.source.name
    for e in scenario.events:
        if not isinstance(e, SetVariable):
            continue
        where = f"{scenario.source}:{e.line}" if e.line else scenario.source
        var = watched.get(e.name)
        if var is None:
            known = ", ".join(watched) or "none"
            raise ScenarioError(f"{where}: var: {e.name} is not a watched (#pragma DATA_SECTION) variable "
                                f"of {lab} (watched: {known})")
        if var.length is None and e.index is not None:
            raise ScenarioError(f"{where}: index: {e.name} is not an array in {lab}")
        if var.length is not None and (e.index is None or e.index >= var.length):
            raise ScenarioError(f"{where}: index: {e.name} has {var.length} elements in {lab}: "
                                f"give an index 0..{var.length - 1}")
        if var.is_integer:
            low, high = _integer_range(var.cdecl)
            if not low <= round(e.value) <= high:
                raise ScenarioError(f"{where}: value: {e.value:g} does not fit {e.name}, "
                                    f"{var.ctype} in {lab} ({low} to {high})")


def _integer_range(cdecl: str) -> tuple[int, int]:
    """The host range of the integer type in a watched variable's declaration.

    >>> _integer_range("extern uint16_t mode;"), _integer_range("extern int count[4];")
    ((0, 65535), (-2147483648, 2147483647))
    """
    from cffi import FFI

    ctype = cdecl.removeprefix("extern ").rsplit(" ", 1)[0]
    if ctype == "_Bool":
        return 0, 1
    ffi = FFI()
    bits = 8 * ffi.sizeof(ctype)
    if int(ffi.cast(ctype, -1)) < 0:
        return -(1 << (bits - 1)), (1 << (bits - 1)) - 1
    return 0, (1 << bits) - 1


def describe_builtins() -> list[tuple[str, str]]:
    """(name, description) of every built-in scenario, the default first."""
    out = [(n, load_scenario(n).description) for n in builtin_names()]
    return sorted(out, key=lambda p: (p[0] != DEFAULT_SCENARIO, p[0]))
