"""The course's friction table: per joint, the lines ``u = Vpos w + Cpos`` (moving positive) and
``u = Vneg w + Cneg`` (moving negative), command units against motor speed ``w`` (rad/s).

A table comes from three places, all as :class:`FrictionTable`:

- the Lab 3 identification's points (``csrc/labs/lab3_friction_id.c`` prints one line per
  constant-speed pass, on crslab's arm or a real one: :func:`parse_points`), fitted line by line
  (:func:`fit_lines`);
- a table file (TOML, :func:`load_table`; the course's own is
  ``models/crs_arm/recordings/lab3_friction_table_course.toml``);
- a plant's friction law (:func:`predict`): the lines the method would find on that arm, the
  law's steady-state command at the table's speeds fitted the same way.

>>> text = "joint 1 speed 0.5000 rad/s command 0.4900\\n\\rjoint 1 speed -0.5000 rad/s command -0.4200\\n\\r"
>>> [(p.joint, p.speed_rad_s, p.command_units) for p in parse_points(text)]
[(1, 0.5, 0.49), (1, -0.5, -0.42)]
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from crslab.plant.plant_params import PlantParams
from crslab.toml_file import read_toml

KEYS = ("Vpos", "Vneg", "Cpos", "Cneg")
"""The four numbers of a joint's row, in the course's order."""
LAB_SPEEDS_RAD_S = (0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0)
"""The motor speeds crslab's Lab 3 lab drives each joint at (its ``speeds_rad_s``)."""
DEFAULT_UNCERTAINTY = 0.10
"""A table file that states no uncertainty: each of its numbers known to 10 % (one standard
deviation), about how much the course's arms differ from one another."""

_POINT = re.compile(r"joint\s+([123])\s+speed\s+(-?\d+(?:\.\d*)?)\s+rad/s\s+command\s+(-?\d+(?:\.\d*)?)")


class FrictionTableError(ValueError):
    """A table file or a log that cannot be used; the message names it and what is wrong."""


@dataclass(frozen=True)
class Point:
    """One constant-speed pass: the joint (1..3), its mean motor speed (rad/s) and the mean command
    (units) that kept it there."""

    joint: int
    speed_rad_s: float
    command_units: float


@dataclass(frozen=True)
class Line:
    """``u = slope w + intercept`` over one direction of one joint, with how well it fits: the RMS
    of the points about it (units; 0 for a table file) and the standard errors of both numbers."""

    slope: float
    intercept: float
    rms_units: float = 0.0
    points: int = 0
    slope_sd: float = 0.0
    intercept_sd: float = 0.0


@dataclass(frozen=True)
class JointRow:
    """A joint's two lines: ``positive`` gives Vpos and Cpos, ``negative`` Vneg and Cneg."""

    positive: Line
    negative: Line

    def value(self, key: str) -> float:
        """``Vpos``, ``Vneg``, ``Cpos`` or ``Cneg``."""
        line = self.positive if key.endswith("pos") else self.negative
        return line.slope if key.startswith("V") else line.intercept


@dataclass(frozen=True)
class FrictionTable:
    """Rows by joint (1..3; a table may hold fewer), where the speeds were, and the relative
    uncertainty of each number (one standard deviation)."""

    rows: Mapping[int, JointRow]
    speeds_rad_s: tuple[float, ...] = LAB_SPEEDS_RAD_S
    uncertainty: float = DEFAULT_UNCERTAINTY
    source: str = ""
    points: tuple[Point, ...] = field(default=(), compare=False)

    def value(self, joint: int, key: str) -> float:
        return self.rows[joint].value(key)

    def values(self) -> dict[tuple[int, str], float]:
        """Every number, by (joint, key)."""
        return {(j, k): self.value(j, k) for j in sorted(self.rows) for k in KEYS}

    def to_toml(self, header: str = "") -> str:
        """The table as a table file (:func:`load_table` reads it back).

        >>> t = FrictionTable({1: JointRow(Line(0.25, 0.36), Line(0.25, -0.3))}, (0.1, 1.0), 0.05, "x")
        >>> print(t.to_toml().split("[joint1]")[1].strip())
        Vpos = 0.25
        Vneg = 0.25
        Cpos = 0.36
        Cneg = -0.3
        """
        lines = [f"# {line}" if line else "#" for line in header.splitlines()]
        lines += ["# Friction in command units against motor speed (rad/s): u = Vpos w + Cpos moving",
                  "# positive, u = Vneg w + Cneg moving negative (crslab friction, crslab identify).",
                  f"uncertainty = {_num(self.uncertainty)}   # relative, of each number, one standard "
                  "deviation",
                  "speeds_rad_s = [" + ", ".join(_num(s) for s in self.speeds_rad_s) + "]"]
        if self.source:
            lines.append(f"source = {_quote(self.source)}")
        for j in sorted(self.rows):
            lines += ["", f"[joint{j}]"] + [f"{k} = {_num(self.value(j, k))}" for k in KEYS]
        return "\n".join(lines) + "\n"


def _num(x: float) -> str:
    return format(float(x), ".6g")


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def parse_points(text: str) -> list[Point]:
    """Every pass the Lab 3 lab reported in ``text`` (its transcript or a Tera Term log), in order."""
    return [Point(int(m.group(1)), float(m.group(2)), float(m.group(3))) for m in _POINT.finditer(text)]


def fit_line(speeds: Sequence[float], commands: Sequence[float]) -> Line:
    """Least-squares line through ``(speed, command)`` points, with its residual and the standard
    errors of slope and intercept (from the residual; 0 with two points).

    >>> line = fit_line([0.1, 0.5, 1.0], [0.4, 0.5, 0.625])
    >>> round(line.slope, 6), round(line.intercept, 6), round(line.rms_units, 9)
    (0.25, 0.375, 0.0)
    """
    w, u = np.asarray(speeds, dtype=float), np.asarray(commands, dtype=float)
    if len(w) < 2 or np.ptp(w) == 0:
        raise FrictionTableError("a line needs points at two speeds at least")
    a = np.column_stack([w, np.ones_like(w)])
    (slope, intercept), *_ = np.linalg.lstsq(a, u, rcond=None)
    residual = u - a @ np.array([slope, intercept])
    rms = float(np.sqrt(np.mean(residual ** 2)))
    slope_sd = intercept_sd = 0.0
    if len(w) > 2:
        s2 = float(residual @ residual) / (len(w) - 2)
        cov = s2 * np.linalg.inv(a.T @ a)
        slope_sd, intercept_sd = float(np.sqrt(cov[0, 0])), float(np.sqrt(cov[1, 1]))
    return Line(float(slope), float(intercept), rms, len(w), slope_sd, intercept_sd)


def fit_lines(points: Iterable[Point], vmin_rad_s: float = 0.0, source: str = "",
              uncertainty: float | None = None) -> FrictionTable:
    """The course's lines through each joint's points faster than ``vmin_rad_s``, each direction on
    its own. ``uncertainty`` None: each line's standard errors, relative to the numbers, the
    largest of them (at least 1 %)."""
    points = list(points)
    rows: dict[int, JointRow] = {}
    for joint in sorted({p.joint for p in points}):
        lines = []
        for sign in (1, -1):
            mine = [p for p in points if p.joint == joint and sign * p.speed_rad_s > vmin_rad_s]
            if len({round(p.speed_rad_s, 6) for p in mine}) < 2:
                word = "positive" if sign > 0 else "negative"
                raise FrictionTableError(f"joint {joint} has fewer than two {word} speeds above "
                                         f"{vmin_rad_s:g} rad/s: no line to fit")
            lines.append(fit_line([p.speed_rad_s for p in mine], [p.command_units for p in mine]))
        rows[joint] = JointRow(*lines)
    if not rows:
        raise FrictionTableError("no 'joint N speed W rad/s command U' lines: not the Lab 3 lab's output")
    # the speeds the passes were asked for (a pass measures its own within a fraction of a percent)
    speeds = tuple(sorted({round(abs(p.speed_rad_s), 2) for p in points if abs(p.speed_rad_s) > vmin_rad_s}))
    if uncertainty is None:
        shares = [max(line.slope_sd / abs(line.slope) if line.slope else 0.0,
                      line.intercept_sd / abs(line.intercept) if line.intercept else 0.0)
                  for row in rows.values() for line in (row.positive, row.negative)]
        uncertainty = max(0.01, max(shares))
    return FrictionTable(rows, speeds, uncertainty, source, tuple(points))


def predict(plant: PlantParams, speeds_rad_s: Sequence[float] = LAB_SPEEDS_RAD_S,
            joints: Iterable[int] = (1, 2, 3)) -> FrictionTable:
    """The table the course's method would measure on an arm with ``plant``'s friction: at a
    constant speed the command equals the friction (gravity averaged out, the drive well inside its
    envelope), so each line is fitted to :meth:`PlantParams.friction_nm` over ``motor_gain`` at
    ``speeds_rad_s``, as :func:`fit_lines` fits a run's points.

    >>> p = PlantParams.defaults()
    >>> t = predict(p)
    >>> abs(t.value(1, "Cpos") - p.coulomb_pos_nm[0] / p.motor_gain) < 0.01
    True
    """
    speeds = [float(s) for s in speeds_rad_s]
    points = [Point(j, sign * w, plant.friction_nm(j, sign * w) / plant.motor_gain)
              for j in joints for sign in (1, -1) for w in speeds]
    return fit_lines(points, source="predicted from the plant's friction")


def load_table(path: str | Path) -> FrictionTable:
    """Read a table file. Raises :class:`FrictionTableError` (one line, naming the file)."""
    path = Path(path)
    data = read_toml(path, "friction table", FrictionTableError)

    def bad(what: str) -> FrictionTableError:
        return FrictionTableError(f"{path}: {what}")

    rows: dict[int, JointRow] = {}
    known = {"uncertainty", "speeds_rad_s", "source", "joint1", "joint2", "joint3"}
    for key in data:
        if key not in known:
            raise bad(f"unknown key {key} (a friction table holds {', '.join(sorted(known))})")
    for j in (1, 2, 3):
        row = data.get(f"joint{j}")
        if row is None:
            continue
        if not isinstance(row, Mapping) or set(row) - {*KEYS, "vmin_rad_s"} or set(KEYS) - set(row):
            raise bad(f"[joint{j}] must give {', '.join(KEYS)} (and may give vmin_rad_s)")
        try:
            v = {k: float(row[k]) for k in KEYS}
        except (TypeError, ValueError):
            raise bad(f"[joint{j}]: every value must be a number") from None
        if not all(math.isfinite(x) for x in v.values()):
            raise bad(f"[joint{j}]: every value must be finite")
        if v["Cpos"] < 0 or v["Cneg"] > 0 or v["Vpos"] < 0 or v["Vneg"] < 0:
            raise bad(f"[joint{j}]: Cpos, Vpos and Vneg must be >= 0 and Cneg <= 0 (friction opposes motion)")
        rows[j] = JointRow(Line(v["Vpos"], v["Cpos"]), Line(v["Vneg"], v["Cneg"]))
    if not rows:
        raise bad("no [joint1], [joint2] or [joint3] table")
    try:
        uncertainty = float(data.get("uncertainty", DEFAULT_UNCERTAINTY))
        speeds = tuple(float(s) for s in data.get("speeds_rad_s", LAB_SPEEDS_RAD_S))
    except (TypeError, ValueError):
        raise bad("uncertainty and speeds_rad_s must be numbers") from None
    if not 0 < uncertainty < 10:
        raise bad(f"uncertainty = {uncertainty:g}: a relative uncertainty is above 0 (0.1 is 10 %)")
    if len(speeds) < 2 or any(not (0 < s < 20) for s in speeds):
        raise bad("speeds_rad_s must be two or more motor speeds above 0 rad/s")
    return FrictionTable(rows, speeds, uncertainty, str(data.get("source", path.name)))


def relative_gaps(measured: FrictionTable, reference: FrictionTable) -> dict[tuple[int, str], float]:
    """``measured / reference - 1`` for every number both tables hold."""
    out = {}
    for (j, k), ref in reference.values().items():
        if j in measured.rows and ref != 0:
            out[(j, k)] = measured.value(j, k) / ref - 1.0
    return out
