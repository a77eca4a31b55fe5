"""Read a scenario from TOML (a built-in name or a file) into a :class:`Scenario`.

A scenario file::

    name = "tour"
    description = "one line shown by `crslab scenarios`"
    end = 24.0                      # simulated seconds; the run ends here

    [[event]]
    at = 5.0                        # simulated seconds
    kind = "hand"                   # move the arm by hand, then hold it there
    motor_deg = [0, 0, 0]           # or dh_deg, xyz_in (elbow-up IK), or pose = "rest"
    duration = 2.0                  # seconds to get there

    [[event]]
    at = 9.0
    kind = "release"                # let go

Every error names the file, the event's line and the key.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from crslab import crs
from crslab.scenario.events import Event, HandMove, HandRelease, seconds_to_tick

BUILTIN_DIR = Path(__file__).resolve().parents[1] / "scenarios"
DEFAULT_SCENARIO = "tour"


class ScenarioError(ValueError):
    """A scenario that cannot be used; the message names file, line and key."""


@dataclass(frozen=True)
class Scenario:
    """A named timeline of events ending at ``end_tick``."""

    name: str
    description: str
    end_tick: int
    events: tuple[Event, ...] = field(default_factory=tuple)
    source: str = ""


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


def _event_lines(text: str) -> list[int]:
    """1-based line numbers of each ``[[event]]`` header, in order."""
    return [i + 1 for i, line in enumerate(text.splitlines()) if line.strip() == "[[event]]"]


class _Reader:
    def __init__(self, path: Path, table: dict, line: int | None) -> None:
        self.path, self.table, self.line = path, table, line

    def fail(self, key: str, why: str) -> ScenarioError:
        where = f"{self.path}:{self.line}" if self.line else str(self.path)
        return ScenarioError(f"{where}: {key}: {why}")

    def number(self, key: str, *, default: float | None = None, minimum: float | None = None) -> float:
        if key not in self.table:
            if default is None:
                raise self.fail(key, "missing")
            return default
        value = self.table[key]
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(key, f"must be a number, got {value!r}")
        if minimum is not None and value < minimum:
            raise self.fail(key, f"must be at least {minimum:g}, got {value!r}")
        return float(value)

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


def _parse_event(r: _Reader) -> Event:
    kind = r.table.get("kind")
    at = seconds_to_tick(r.number("at", minimum=0.0))
    if kind == "hand":
        r.check_keys({"at", "kind", "motor_deg", "dh_deg", "xyz_in", "pose", "duration"})
        duration = seconds_to_tick(r.number("duration", default=1.0, minimum=0.0))
        return HandMove(tick=at, target_dh_rad=_hand_target(r), duration_ticks=duration)
    if kind == "release":
        r.check_keys({"at", "kind"})
        return HandRelease(tick=at)
    raise r.fail("kind", f"unknown event kind {kind!r} (known: hand, release)")


def load_scenario(name_or_path: str | None = None) -> Scenario:
    """Load and check a scenario; raises :class:`ScenarioError` naming file, line and key.

    >>> s = load_scenario("tour")
    >>> s.name, s.end_tick > 0, s.events[0].kind
    ('tour', True, 'hand')
    """
    path = resolve(name_or_path)
    text = path.read_text()
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from None
    top = _Reader(path, doc, None)
    top.check_keys({"name", "description", "end", "event"})
    raw_events = doc.get("event", [])
    if not isinstance(raw_events, list):
        raise top.fail("event", "must be an array of tables ([[event]])")
    lines = _event_lines(text)
    events = []
    for i, table in enumerate(raw_events):
        if not isinstance(table, dict):
            raise top.fail("event", "must be an array of tables ([[event]])")
        events.append(_parse_event(_Reader(path, table, lines[i] if i < len(lines) else None)))
    events.sort(key=lambda e: e.tick)
    end_tick = seconds_to_tick(top.number("end", minimum=0.001))
    return Scenario(
        name=str(doc.get("name", path.stem)),
        description=str(doc.get("description", "")),
        end_tick=end_tick,
        events=tuple(events),
        source=str(path),
    )
