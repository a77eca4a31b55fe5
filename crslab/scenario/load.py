"""Read a scenario from TOML (a built-in name or a file) into a :class:`Scenario`.

The format is docs/scenarios.md's: top-level ``name``, ``description``, ``end`` (simulated
seconds) and ``seed``, an optional ``[plant]`` table
(:func:`crslab.scenario.plant_events.parse_plant`) and ``[[event]]`` tables, each of a kind
:data:`crslab.scenario.kinds.EVENT_KINDS` knows.

Every error names the file, the line and the key, and nothing runs.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from crslab import resources
from crslab.framework_facts import TICKS_PER_S
from crslab.lab.build import LabBuild
from crslab.lab.watched import WatchedError, watched_var
from crslab.scenario.event import LONGEST_S, Event, RandomFaults, seconds_to_tick
from crslab.scenario.expect_events import Expect
from crslab.scenario.file_table import ScenarioError
from crslab.scenario.kinds import parse_event
from crslab.scenario.lab_events import SetVariable
from crslab.scenario.plant_events import parse_plant
from crslab.toml_file import TomlFile

BUILTIN_DIR = resources.path("scenarios")
DEFAULT_SCENARIO = "tour"
DEFAULT_SEED = 1


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


def parse_scenario(text: str, path: Path) -> Scenario:
    """Check and parse scenario ``text`` read from ``path`` (named in errors), through the checked
    reader (:class:`crslab.toml_file.TomlFile`: a size limit, bounded nesting and numbers).

    >>> parse_scenario('end = 2.0\\n[[event]]\\nat = 1\\nkind = "estop"\\n', Path("x.toml")).events
    (WristEstop(tick=1000, line=4, wrist_rad=0.2),)
    >>> parse_scenario('end = 2.0\\n[[event]]\\nat = 1\\nkind = "nap"\\n', Path("x.toml"))
    Traceback (most recent call last):
    ...
    crslab.scenario.file_table.ScenarioError: x.toml:4: kind: unknown event kind 'nap' (known: ...)
    """
    return _scenario(TomlFile.parse(text, str(path), ScenarioError), path)


def _scenario(doc: TomlFile, path: Path) -> Scenario:
    """The scenario of the checked file ``doc`` (read from ``path``)."""
    top = doc.table()
    top.check_keys({"name", "description", "end", "seed", "plant", "event"})
    for key in ("name", "description"):
        if key in top:
            top.text(key)
    seed = top.integer("seed", minimum=0, maximum=2**63 - 1) if "seed" in top else DEFAULT_SEED
    end_tick = seconds_to_tick(top.number("end", minimum=0.001, maximum=LONGEST_S))
    rest, events = None, []
    if "plant" in top:
        rest, events = parse_plant(doc.table(("plant",)))
    faults = RandomFaults(seed)
    for r in doc.tables("event"):
        parsed = parse_event(r, faults)
        if parsed and parsed[0].tick > end_tick:
            raise r.fail("at", f"{parsed[0].tick / TICKS_PER_S:g} s is after the end "
                               f"({end_tick / TICKS_PER_S:g} s)")
        events.extend(parsed)
    events.sort(key=lambda e: e.tick)  # stable: events at the same tick keep their file order
    return Scenario(
        name=str(doc.data.get("name", path.stem)),
        description=str(doc.data.get("description", "")),
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
    return _scenario(TomlFile.read(path, "scenario file", ScenarioError), path)


def check_lab(scenario: Scenario, build: LabBuild) -> None:
    """Check that every variable the scenario writes (``set``) or expects (``expect``) is one the
    lab watches (``#pragma DATA_SECTION``), with an index exactly when it is an array, and that
    every value written fits; raises :class:`ScenarioError` naming the file, the line and the key."""
    lab = build.source.name
    for e in scenario.events:
        if isinstance(e, SetVariable):
            name, index, line = e.name, e.index, e.line
        elif isinstance(e, Expect) and e.variable is not None:
            name, index, line = e.variable.name, e.variable.index, e.variable.line or e.line
        else:
            continue
        try:
            var = watched_var(build.watched, name, index, lab)
            if isinstance(e, SetVariable):
                var.check_value(e.value, lab)
        except WatchedError as exc:
            where = f"{scenario.source}:{line}" if line else scenario.source
            raise ScenarioError(f"{where}: {exc.key}: {exc}") from None


def describe_builtins() -> list[tuple[str, str]]:
    """(name, description) of every built-in scenario, the default first."""
    out = [(n, load_scenario(n).description) for n in builtin_names()]
    return sorted(out, key=lambda p: (p[0] != DEFAULT_SCENARIO, p[0]))
