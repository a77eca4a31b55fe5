"""Reading one table of a scenario file (the top level, ``[plant]`` or one ``[[event]]``) with
errors that name the file, the line and the key; and the fields several event kinds share."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from crslab import crs
from crslab.plant.model_files import COURSE_END_MASS_KG

_HEADER = re.compile(r"^\s*\[")


class ScenarioError(ValueError):
    """A scenario that cannot be used; the message names file, line and key."""


class TableReader:
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


def hand_target(r: TableReader) -> tuple[float, float, float] | None:
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


def joint_numbers(r: TableReader) -> tuple[int, ...]:
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


def per_joint(r: TableReader, key: str, *, whole: bool, minimum: float | None = None) -> tuple[float, ...]:
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
        joints = joint_numbers(r)
        values = [float(value) if j + 1 in joints else 0.0 for j in range(3)]
        raw = [value]
    if whole and not all(isinstance(v, int) for v in raw):
        raise r.fail(key, f"must be whole numbers of counts, got {value!r}")
    if minimum is not None and any(v < minimum for v in values):
        raise r.fail(key, f"must be at least {minimum:g}, got {value!r}")
    return tuple(values)


def end_mass_kg(r: TableReader, key: str) -> float:
    value = r.table.get(key)
    if value == "course":
        return COURSE_END_MASS_KG
    if isinstance(value, str):
        raise r.fail(key, f"must be a number of kg or \"course\", got {value!r}")
    return r.number(key, minimum=0.0)
