"""Checks of the running lab: ``expect``, what must be true at a time (the motor board, the safety
flag, the arm's angles, a watched variable).

An expectation at tick k looks at the run as it stands when its tick comes, before tick k runs,
like every event: the motor board and the safety flag as tick k-1 left them (the flag is the
``error`` lab() gets at tick k), the arm's motor angles after k physics steps (what tick k's
encoders read, for a lab with the right offsets and no encoder fault), a watched variable's
value. It never changes the run: the worker only reads (``crslab/worker/event_effects.py``) and
sends what it saw as an :class:`Observation`; the crslab process judges it (:class:`Judge`), so
what counts as met is decided outside the lab's process.

>>> from crslab.scenario.load import parse_scenario
>>> text = 'end = 9\\n[[event]]\\nat = 6\\nkind = "expect"\\nmotor_board_off = true\\nerror = 0\\n'
>>> e = parse_scenario(text, Path("cut.toml")).events[0]
>>> e.describe()
'expect the motor board off, error = 0'
>>> seen = Observation(tick=6000, motor_board="piccolo", motor_board_off=False, motor_board_cutouts=0,
...                    error=0, motor_rad=(0.0, 0.0, 0.0))
>>> [c.failure(seen, {}) for c in e.conditions]
['expected the motor board off, it was on', None]
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from crslab import crs
from crslab.framework_facts import TICKS_PER_S
from crslab.scenario.event import LONGEST_S, Event, RandomFaults, seconds_to_tick
from crslab.scenario.file_table import joint_numbers
from crslab.toml_file import Table

DEFAULT_TOL_DEG = 1.0
"""How close an expected angle must be when the file gives no ``tol_deg`` or ``tol_rad``."""
_IDENTIFIER = re.compile(r"[A-Za-z_]\w*\Z")
_ANGLE_KEYS = ("motor_deg", "motor_rad", "dh_deg")
WORLD_RANGES = {"egg_force": ("the egg's force", "N"), "scale_g": ("the scale", "g"),
                "peg_depth": ("the peg's depth in the hole", "m")}
"""World quantities an expectation may bound (``egg_force = [low, high]``): what, unit."""
CONTACT_FIXTURES = ("table", "hole", "obstacle", "groove", "egg")
"""Fixtures ``contact.NAME = true|false`` may name (touched by the peg, or any arm link for the obstacle)."""
CONDITION_KEYS = ("motor_board_off", "motor_board_cutouts", "error", *_ANGLE_KEYS, "moved_deg", "var",
                  *WORLD_RANGES, "egg_broken", "contact")
"""The keys of an ``expect`` table that are conditions (the others qualify them)."""


@dataclass(frozen=True)
class Observation:
    """What the worker saw when an expectation's tick came (before that tick ran)."""

    tick: int
    motor_board: str
    """The run's motor board (``none`` or ``piccolo``)."""
    motor_board_off: bool
    """The motor board has cut every output (as tick - 1 left it)."""
    motor_board_cutouts: int
    """Cut-outs started so far."""
    error: int
    """The safety flag lab() gets at this tick: 1 when the last tick found the arm outside the
    safety envelope (0 before lab() first ran)."""
    motor_rad: tuple[float, float, float]
    """The arm's motor angles (rad), as a lab with the right offsets reads them."""
    var: float | None = None
    """The watched variable the expectation names (None when it names none)."""
    world: Mapping[str, float] | None = None
    """The world's quantities of the last step (``egg_force``, ``scale_g``, ``egg_broken``,
    ``peg_depth``, ``hole_force``...; crslab.world.world_facts.WORLD_COLUMNS); None in free air."""


def _joints_text(joints: tuple[int, ...], what: str) -> str:
    """``what`` ("motor angle") of ``joints``, as a phrase.

    >>> _joints_text((1, 2, 3), "motor angle"), _joints_text((2,), "DH angle")
    ('motor angles', 'joint 2 DH angle')
    """
    if joints == (1, 2, 3):
        return what + "s"
    if len(joints) == 1:
        return f"joint {joints[0]} {what}"
    return f"joints {', '.join(map(str, joints))} {what}s"


def _values_text(values_rad: Sequence[float], unit: str) -> str:
    """Angles as written in messages: ``90.00 deg``, ``(0.00, 90.00) deg``, ``1.5708 rad``."""
    shown = [f"{math.degrees(v):.2f}" if unit == "deg" else f"{v:.4f}" for v in values_rad]
    return (shown[0] if len(shown) == 1 else "(" + ", ".join(shown) + ")") + f" {unit}"


def _tol_text(tol_rad: float, unit: str) -> str:
    return f"{math.degrees(tol_rad):g} deg" if unit == "deg" else f"{tol_rad:g} rad"


class Condition:
    """One thing an expectation checks. Each kind is a frozen dataclass with :meth:`describe` and
    :meth:`failure`."""

    def describe(self) -> str:
        """What must be true, in a few words (``expect ...`` in timelines)."""
        raise NotImplementedError

    def failure(self, seen: Observation, earlier: Mapping[int, Observation]) -> str | None:
        """Why ``seen`` does not meet the condition (``expected ..., it was ...``), or None when it
        does. ``earlier`` holds the observations of earlier ticks, by tick."""
        raise NotImplementedError


@dataclass(frozen=True)
class BoardOff(Condition):
    """The motor board has cut every output (``off``), or has not.

    >>> BoardOff(False).describe()
    'the motor board on'
    """

    off: bool

    def describe(self) -> str:
        return f"the motor board {'off' if self.off else 'on'}"

    def failure(self, seen: Observation, earlier: Mapping[int, Observation]) -> str | None:
        if seen.motor_board_off == self.off:
            return None
        why = f"expected {self.describe()}, it was {'off' if seen.motor_board_off else 'on'}"
        if seen.motor_board == "none":
            why += " (this run has no motor board: --motor-board none)"
        return why


@dataclass(frozen=True)
class Cutouts(Condition):
    """Exactly ``count`` motor-board cut-outs have started so far.

    >>> Cutouts(1).describe()
    '1 motor-board cut-out so far'
    """

    count: int

    def describe(self) -> str:
        return f"{self.count} motor-board cut-out{'' if self.count == 1 else 's'} so far"

    def failure(self, seen: Observation, earlier: Mapping[int, Observation]) -> str | None:
        if seen.motor_board_cutouts == self.count:
            return None
        return f"expected {self.describe()}, there were {seen.motor_board_cutouts}"


@dataclass(frozen=True)
class SafetyFlag(Condition):
    """The ``error`` lab() gets at this tick is ``flag`` (1: the arm was outside the envelope)."""

    flag: int

    def describe(self) -> str:
        return f"error = {self.flag}"

    def failure(self, seen: Observation, earlier: Mapping[int, Observation]) -> str | None:
        if seen.error == self.flag:
            return None
        where = "outside" if self.flag else "inside"
        return f"expected error = {self.flag} (the arm {where} the safety envelope), it was {seen.error}"


@dataclass(frozen=True)
class Angles(Condition):
    """The arm's ``frame`` (``motor`` or ``DH``) angles of ``joints`` are ``values_rad`` (one per
    joint named) within ``tol_rad``; messages show them in ``unit`` (``deg`` or ``rad``).

    >>> Angles("motor", (0.0, math.pi / 2, 0.0), (1, 2, 3), math.radians(1), "deg").describe()
    'motor angles (0.00, 90.00, 0.00) deg within 1 deg'
    """

    frame: str
    values_rad: tuple[float, ...]
    joints: tuple[int, ...]
    tol_rad: float
    unit: str

    def describe(self) -> str:
        what = _joints_text(self.joints, f"{self.frame} angle")
        within = _tol_text(self.tol_rad, self.unit)
        return f"{what} {_values_text(self.values_rad, self.unit)} within {within}"

    def failure(self, seen: Observation, earlier: Mapping[int, Observation]) -> str | None:
        now = np.asarray(seen.motor_rad) if self.frame == "motor" else crs.motor_to_dh(seen.motor_rad)
        got = [float(now[j - 1]) for j in self.joints]
        off = [abs(g - v) for g, v in zip(got, self.values_rad)]
        if all(o <= self.tol_rad + 1e-12 for o in off):
            return None
        worst = max(range(len(off)), key=off.__getitem__)
        joint = f"joint {self.joints[worst]} " if len(self.joints) > 1 else ""
        verb = "they were" if len(self.joints) > 1 else "it was"
        return (f"expected {self.describe()}, {verb} {_values_text(got, self.unit)} ({joint}off by "
                f"{_values_text([off[worst]], self.unit)})")


@dataclass(frozen=True)
class Moved(Condition):
    """Each of ``joints``' motor angles moved by at least ``|by_rad|`` in ``by_rad``'s direction
    since ``since_tick``.

    >>> Moved(math.radians(1), (1,), 5000).describe()
    'joint 1 motor angle up by at least 1 deg since 5 s'
    """

    by_rad: float
    joints: tuple[int, ...]
    since_tick: int

    def describe(self) -> str:
        way = "up" if self.by_rad > 0 else "down"
        what = _joints_text(self.joints, "motor angle")
        by = math.degrees(abs(self.by_rad))
        return f"{what} {way} by at least {by:g} deg since {self.since_tick / TICKS_PER_S:g} s"

    def failure(self, seen: Observation, earlier: Mapping[int, Observation]) -> str | None:
        before = earlier.get(self.since_tick)
        if before is None:  # pragma: no cover - the parser notes the angles at since_tick
            since_s = self.since_tick / TICKS_PER_S
            return f"expected {self.describe()}: the angles at {since_s:g} s were not noted"
        moved = [seen.motor_rad[j - 1] - before.motor_rad[j - 1] for j in self.joints]
        if all(m * math.copysign(1.0, self.by_rad) >= abs(self.by_rad) for m in moved):
            return None
        verb = "they moved" if len(self.joints) > 1 else "it moved"
        return f"expected {self.describe()}, {verb} by {_values_text(moved, 'deg')}"


@dataclass(frozen=True)
class Variable(Condition):
    """The lab's watched variable ``name`` (element ``index`` of an array) is ``value`` within
    ``tol``. ``line`` is where the file names it (what errors about it point at).

    >>> Variable("Kp1", None, 2.5, 0.0).describe(), Variable("gains", 1, 2.0, 0.1).describe()
    ('Kp1 = 2.5', 'gains[1] = 2 within 0.1')
    """

    name: str
    index: int | None
    value: float
    tol: float
    line: int = field(default=0, compare=False)

    def describe(self) -> str:
        where = self.name if self.index is None else f"{self.name}[{self.index}]"
        return f"{where} = {self.value:g}" + (f" within {self.tol:g}" if self.tol else "")

    def failure(self, seen: Observation, earlier: Mapping[int, Observation]) -> str | None:
        got = seen.var
        if got is not None and abs(got - self.value) <= self.tol:
            return None
        return f"expected {self.describe()}, it was {got:g}" if got is not None else \
            f"expected {self.describe()}, it could not be read"


def _world_value(seen: Observation, key: str) -> float | None:
    return None if seen.world is None or key not in seen.world else float(seen.world[key])


_NO_WORLD = "this run's world has no fixtures (give --world)"


@dataclass(frozen=True)
class WorldRange(Condition):
    """A world quantity (``egg_force`` N, ``scale_g`` g, ``peg_depth`` m) lies within ``[low, high]``.

    >>> WorldRange("scale_g", 500.0, 1000.0).describe()
    'the scale within [500, 1000] g'
    """

    key: str
    low: float
    high: float

    def describe(self) -> str:
        what, unit = WORLD_RANGES[self.key]
        return f"{what} within [{self.low:g}, {self.high:g}] {unit}"

    def failure(self, seen: Observation, earlier: Mapping[int, Observation]) -> str | None:
        got = _world_value(seen, self.key)
        if got is None:
            return f"expected {self.describe()}: {_NO_WORLD}"
        if self.low <= got <= self.high:
            return None
        return f"expected {self.describe()}, it was {got:.4g} {WORLD_RANGES[self.key][1]}"


@dataclass(frozen=True)
class EggBroken(Condition):
    """The egg is broken (``broken``), or whole."""

    broken: bool

    def describe(self) -> str:
        return "the egg broken" if self.broken else "the egg whole"

    def failure(self, seen: Observation, earlier: Mapping[int, Observation]) -> str | None:
        got = _world_value(seen, "egg_broken")
        if got is None:
            return f"expected {self.describe()}: {_NO_WORLD}"
        if bool(got) == self.broken:
            return None
        return f"expected {self.describe()}, it was {'broken' if got else 'whole'}"


@dataclass(frozen=True)
class Contact(Condition):
    """The peg (any arm link, for the obstacle) touches ``fixture`` (``touching``), or does not.

    >>> Contact("hole", True).describe()
    'a contact with the hole block'
    """

    fixture: str
    touching: bool

    def describe(self) -> str:
        names = {"hole": "the hole block", "groove": "the groove plate"}
        name = names.get(self.fixture, f"the {self.fixture}")
        return f"{'a' if self.touching else 'no'} contact with {name}"

    def failure(self, seen: Observation, earlier: Mapping[int, Observation]) -> str | None:
        got = _world_value(seen, f"{self.fixture}_force")
        if got is None:
            return f"expected {self.describe()}: {_NO_WORLD}"
        if (got > 0.0) == self.touching:
            return None
        return f"expected {self.describe()}, the force on it was {got:.4g} N"


def _world(r: Table) -> list[Condition]:
    """``egg_force``/``scale_g``/``peg_depth`` = [low, high], ``egg_broken``, ``contact.NAME``."""
    out: list[Condition] = []
    for key in WORLD_RANGES:
        if key in r.table:
            v = r.table[key]
            numbers = isinstance(v, list) and all(
                isinstance(x, int | float) and not isinstance(x, bool) for x in v)
            if not numbers or len(v) != 2 or v[0] > v[1]:
                raise r.fail(key, f"must be a range [low, high], got {v!r}")
            out.append(WorldRange(key, float(v[0]), float(v[1])))
    if "egg_broken" in r.table:
        if not isinstance(r.table["egg_broken"], bool):
            raise r.fail("egg_broken", f"must be true or false, got {r.table['egg_broken']!r}")
        out.append(EggBroken(r.table["egg_broken"]))
    if "contact" in r.table:
        table = r.table["contact"]
        if not isinstance(table, dict) or not table:
            raise r.fail("contact", "must name a fixture: contact.hole = true (fixtures: "
                         f"{', '.join(CONTACT_FIXTURES)})")
        for name, value in table.items():
            if name not in CONTACT_FIXTURES:
                fixtures = ", ".join(CONTACT_FIXTURES)
                raise r.fail(f"contact.{name}", f"no fixture {name!r} (fixtures: {fixtures})")
            if not isinstance(value, bool):
                raise r.fail(f"contact.{name}", f"must be true or false, got {value!r}")
            out.append(Contact(name, value))
    return out


@dataclass(frozen=True)
class Expect(Event):
    """Check ``conditions`` against the run when its tick comes; ``message`` is the file's own
    words, shown when one fails. An expectation without conditions only notes the arm's angles
    for a later ``moved_deg`` (``note_for``: the tick of that expectation)."""

    conditions: tuple[Condition, ...]
    message: str = ""
    note_for: int | None = None
    kinds = ("expect",)

    @property
    def variable(self) -> Variable | None:
        """The watched variable the expectation reads, if any."""
        return next((c for c in self.conditions if isinstance(c, Variable)), None)

    @classmethod
    def parse(cls, r: Table, at: int, line: int, faults: RandomFaults) -> list[Event]:
        r.check_keys({"at", "kind", "message", *CONDITION_KEYS, "tol_deg", "tol_rad", "since", "joint",
                      "joints", "index", "value", "tol"})
        conditions: list[Condition] = []
        if "motor_board_off" in r.table:
            if not isinstance(r.table["motor_board_off"], bool):
                raise r.fail("motor_board_off", f"must be true or false, got {r.table['motor_board_off']!r}")
            conditions.append(BoardOff(r.table["motor_board_off"]))
        if "motor_board_cutouts" in r.table:
            conditions.append(Cutouts(r.integer("motor_board_cutouts", minimum=0, maximum=2**31 - 1)))
        if "error" in r.table:
            conditions.append(SafetyFlag(r.integer("error", minimum=0, maximum=1)))
        conditions.extend(_angles(r))
        moved, note = _moved(r, at, line)
        conditions.extend(moved)
        conditions.extend(_variable(r))
        conditions.extend(_world(r))
        if not conditions:
            raise r.fail("kind", "an expectation needs a condition (one or more of: "
                         f"{', '.join(CONDITION_KEYS)})")
        message = r.text("message") if "message" in r.table else ""
        return [cls(tick=at, conditions=tuple(conditions), message=message, line=line), *note]

    def describe(self) -> str:
        if self.note_for is not None:
            return f"expect: note the motor angles (for the expectation at {self.note_for / TICKS_PER_S:g} s)"
        return "expect " + ", ".join(c.describe() for c in self.conditions)


def _angles(r: Table) -> list[Condition]:
    """``motor_deg``, ``motor_rad`` or ``dh_deg`` with ``tol_deg`` or ``tol_rad``."""
    given = [k for k in _ANGLE_KEYS if k in r.table]
    for key in ("tol_deg", "tol_rad"):
        if key in r.table and not given:
            raise r.fail(key, f"only with {', '.join(_ANGLE_KEYS)}")
    if "tol_deg" in r.table and "tol_rad" in r.table:
        raise r.fail("tol_rad", "give tol_deg or tol_rad, not both")
    if not given:
        return []
    if len(given) > 1:
        raise r.fail(given[1], f"give one of {', '.join(_ANGLE_KEYS)}, not several")
    key = given[0]
    tol = (r.number("tol_rad", minimum=0.0) if "tol_rad" in r.table
           else math.radians(r.number("tol_deg", default=DEFAULT_TOL_DEG, minimum=0.0)))
    values, joints = _per_joint_values(r, key)
    rad = tuple(math.radians(v) for v in values) if key.endswith("deg") else values
    return [Angles("motor" if key.startswith("motor") else "DH", rad, joints, tol, key[-3:])]


def _per_joint_values(r: Table, key: str) -> tuple[tuple[float, ...], tuple[int, ...]]:
    """A list of three (every joint) or one number for ``joint``/``joints``."""
    value = r.table[key]
    if isinstance(value, list):
        if "joint" in r.table or "joints" in r.table:
            also = " (to choose the joints of moved_deg, give it an expectation of its own)" \
                if "moved_deg" in r.table else ""
            raise r.fail(key, f"a list gives every joint its value: leave out joint/joints{also}")
        return tuple(float(v) for v in r.triple(key)), (1, 2, 3)
    if "joint" not in r.table and "joints" not in r.table:
        raise r.fail(key, f"must be a list of three numbers, or one number with joint or joints, "
                     f"got {value!r}")
    joints = joint_numbers(r)
    return (r.number(key),) * len(joints), joints


def _moved(r: Table, at: int, line: int) -> tuple[list[Condition], list[Event]]:
    """``moved_deg`` since ``since``: the condition, and the event that notes the angles then."""
    if "moved_deg" not in r.table:
        if "since" in r.table:
            raise r.fail("since", "only with moved_deg")
        if ("joint" in r.table or "joints" in r.table) and not any(
                k in r.table and not isinstance(r.table[k], list) for k in _ANGLE_KEYS):
            key = "joint" if "joint" in r.table else "joints"
            raise r.fail(key, "only with moved_deg, or one number of motor_deg, motor_rad or dh_deg")
        return [], []
    if isinstance(r.table["moved_deg"], list):
        raise r.fail("moved_deg", "must be one number of degrees (choose the joints with joint or joints)")
    by = r.number("moved_deg")
    if by == 0:
        raise r.fail("moved_deg", "must not be 0: its sign says which way the angle must move")
    if "since" not in r.table:
        raise r.fail("since", "missing (moved_deg counts from the motor angles at this time, in seconds)")
    since = seconds_to_tick(r.number("since", minimum=0.0, maximum=LONGEST_S))
    if since >= at:
        raise r.fail("since", "must be earlier than at")
    note = Expect(tick=since, conditions=(), note_for=at, line=line)
    return [Moved(math.radians(by), joint_numbers(r), since)], [note]


def _variable(r: Table) -> list[Condition]:
    """``var`` with ``value``, optional ``index`` and ``tol``."""
    if "var" not in r.table:
        for key in ("value", "index", "tol"):
            if key in r.table:
                raise r.fail(key, "only with var")
        return []
    name = r.text("var")
    if not _IDENTIFIER.match(name):
        raise r.fail("var", f"must be a C variable name, got {name!r}")
    index = r.integer("index", minimum=0) if "index" in r.table else None
    tol = r.number("tol", default=0.0, minimum=0.0)
    return [Variable(name, index, r.number("value"), tol, line=r.line_of("var") or 0)]


@dataclass(frozen=True)
class ExpectOutcome:
    """How one expectation went: met, failed (``failures``, one sentence per failed condition) or
    not reached (the run ended first). ``where`` is ``file:line``; ``what`` its description."""

    tick: int
    where: str
    what: str
    message: str = ""
    failures: tuple[str, ...] = ()
    reached: bool = True

    @property
    def met(self) -> bool:
        """True when the run reached it and every condition held."""
        return self.reached and not self.failures

    def lines(self) -> list[str]:
        """One line per failed condition: when, why, where, and the file's message.

        >>> ExpectOutcome(6000, "cut.toml:9", "", "joint 1 saturates",
        ...               ("expected the motor board off, it was on",)).lines()
        ['t = 6.000 s: expected the motor board off, it was on (cut.toml:9): joint 1 saturates']
        """
        tail = f": {self.message}" if self.message else ""
        return [f"t = {self.tick / TICKS_PER_S:.3f} s: {why} ({self.where}){tail}" for why in self.failures]

    def as_dict(self) -> dict:
        """For ``--json``: when, where, what, met (None: not reached), the failures, the message."""
        return {"t_s": self.tick / TICKS_PER_S, "where": self.where, "expect": self.what,
                "met": self.met if self.reached else None, "failures": list(self.failures),
                "message": self.message}


class Judge:
    """Judges a run's expectations as their observations arrive, in the order the worker applies
    them (the scenario's order): the k-th observation is the k-th :class:`Expect` event's."""

    def __init__(self, events: Sequence[Event], source: str = "") -> None:
        self.expects = [e for e in events if isinstance(e, Expect)]
        self.name = Path(source).name if source else "scenario"
        self.seen: dict[int, Observation] = {}
        self.outcomes: list[ExpectOutcome] = []
        self.next = 0

    def observed(self, seen: Observation) -> ExpectOutcome | None:
        """The outcome of the expectation ``seen`` belongs to (None for a note of angles). Raises
        ``ValueError`` when the worker sent more observations, or at other ticks, than due."""
        if self.next >= len(self.expects) or self.expects[self.next].tick != seen.tick:
            raise ValueError(f"an observation at tick {seen.tick} that no expectation asked for")
        e = self.expects[self.next]
        self.next += 1
        self.seen.setdefault(seen.tick, seen)
        if e.note_for is not None:
            return None
        failures = tuple(f for f in (c.failure(seen, self.seen) for c in e.conditions) if f is not None)
        outcome = ExpectOutcome(e.tick, self._where(e), e.describe().removeprefix("expect "), e.message,
                                failures)
        self.outcomes.append(outcome)
        return outcome

    def _where(self, e: Event) -> str:
        return f"{self.name}:{e.line}" if e.line else self.name

    def results(self) -> list[ExpectOutcome]:
        """Every expectation's outcome: those judged, then those the run never reached."""
        later = [ExpectOutcome(e.tick, self._where(e), e.describe().removeprefix("expect "), e.message,
                               reached=False)
                 for e in self.expects[self.next:] if e.note_for is None]
        return [*self.outcomes, *later]


def summary_text(met: int, failed: int, not_reached: int) -> str:
    """``expectations: 3 met, 1 failed, 2 not reached`` (leaving out a count of 0 but the met).

    >>> summary_text(1, 1, 0)
    'expectations: 1 met, 1 failed'
    """
    parts = [f"{met} met"] + ([f"{failed} failed"] if failed else []) + (
        [f"{not_reached} not reached"] if not_reached else [])
    return "expectations: " + ", ".join(parts)
