"""The course robots as data: one TOML file per robot in this folder (see README.md here).

:func:`load` reads a built-in robot by name or any robot file by path and returns a
:class:`Robot`: its DH :class:`~crslab.chain.Chain` (limits, base and tool included), the
points it marks in its frames (joint centres), and which closed-form IK fits it. A file that
is malformed raises :class:`RobotFileError`, one line naming the file and the key.

>>> panda = load("panda")
>>> panda.chain.n_joints, panda.convention, panda.length_unit
(7, 'standard', 'm')
>>> names()
['arm7r', 'crs', 'panda', 'panda_mdh', 'planar3r', 'rrr']
"""

from __future__ import annotations

import ast
import math
import operator
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from crslab import crs, resources
from crslab.chain import CONVENTIONS, FIXED, JOINT_TYPES, MODIFIED, REVOLUTE, STANDARD, Chain
from crslab.closed_ik import (
    OK,
    OUT_OF_LIMITS,
    SINGULAR_BASE,
    SINGULAR_CENTRE,
    UNREACHABLE,
    Solutions,
    planar3r_ik,
    rrr_ik,
)
from crslab.rotation import euler_zyx_to_matrix
from crslab.toml_file import read_toml

HERE = resources.path("robots")
LENGTH_UNITS = ("m", "cm", "mm", "in", "units")
CLOSED_FORMS = ("crs", "planar_3r", "spatial_rrr")
TOP_KEYS = {"name", "title", "source", "convention", "length_unit", "closed_form", "parameters", "dh", "base",
            "tool", "notes"}
ROW_KEYS = {"a", "alpha", "d", "theta", "joint", "lower", "upper", "centre", "name"}
POSE_KEYS = {"xyz", "euler_zyx"}
_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
        ast.Pow: operator.pow, ast.USub: operator.neg, ast.UAdd: operator.pos}


class RobotFileError(ValueError):
    """A robot file that cannot be used; the message names the file and the key."""


@dataclass(frozen=True)
class Robot:
    """One robot read from its file. Angles are in rad, lengths in ``length_unit``."""

    name: str
    title: str
    source: str
    path: Path
    convention: str
    length_unit: str
    chain: Chain
    closed_form: str | None
    parameters: dict[str, float] = field(default_factory=dict)
    centres: np.ndarray | None = None
    row_names: tuple[str, ...] = ()

    @property
    def n_joints(self) -> int:
        """Joint variables per configuration."""
        return self.chain.n_joints

    @property
    def planar(self) -> bool:
        """True when every twist and offset along z is zero: the arm moves in its x-y plane."""
        c = self.chain
        return (bool(np.allclose(np.sin(c.alpha_rad), 0) and np.allclose(c.d, 0)) and c.base is None
                and c.tool is None)

    def fk(self, q_rad: object) -> np.ndarray:
        """End-effector poses ``(..., 4, 4)`` for joint angles ``(..., joints)`` in rad."""
        return self.chain.fk(q_rad)

    def joint_centres(self, q_rad: object) -> np.ndarray | None:
        """World positions of the points the file marks in each frame, ``(..., rows, 3)``."""
        return None if self.centres is None else self.chain.points(q_rad, self.centres)

    def closed_ik(self, target: object) -> Solutions:
        """Every closed-form solution (DH joint angles) of ``target`` ``(..., 3)``.

        The target is x y z for the CRS and RRR arms, x y phi_rad for the planar 3R arm.
        """
        if self.closed_form is None:
            raise ValueError(f"robot {self.name!r} has no closed-form IK; use crslab.chain_ik.ik")
        c = self.chain
        if self.closed_form == "spatial_rrr":
            return rrr_ik((c.d[0], c.a[0], c.a[1], c.a[2]), target, c.lower, c.upper)
        if self.closed_form == "planar_3r":
            return planar3r_ik(c.a, target, c.lower, c.upper)
        return _crs_closed_ik(c, target)


def _crs_closed_ik(chain: Chain, target: object) -> Solutions:
    """The foundation's CRS IK (crslab.crs), both elbows, in DH angles, with this file's limits."""
    xyz = np.asarray(target, dtype=float)
    qs, statuses, shoulder = [], [], False
    for elbow in ("up", "down"):
        motor, status = crs.ik_with_status(xyz, elbow)
        dh = crs.motor_to_dh(motor)
        ok = status != crs.IK_UNREACHABLE  # on the shoulder centre every th2 is exact
        statuses.append(np.where(ok, np.where(chain.within_limits(dh), OK, OUT_OF_LIMITS), UNREACHABLE))
        qs.append(dh)
        shoulder = shoulder | (status == crs.IK_SHOULDER)
    on_axis = np.hypot(xyz[..., 0], xyz[..., 1]) <= 1e-9
    singular = np.where(on_axis, SINGULAR_BASE, 0) | np.where(shoulder, SINGULAR_CENTRE, 0)
    return Solutions(np.stack(qs, -2), np.stack(statuses, -1).astype(np.int32), singular.astype(np.int32),
                     ("elbow up, th3 >= 0", "elbow down, th3 <= 0"))


def names() -> list[str]:
    """The built-in robots (files in this folder)."""
    return sorted(p.stem for p in HERE.glob("*.toml"))


def robot_path(name_or_path: str | Path) -> Path:
    """The file of a built-in robot name, or the given path to a robot file."""
    text = str(name_or_path)
    if text.endswith(".toml") or "/" in text or "\\" in text:
        return Path(text)
    path = HERE / f"{text}.toml"
    if not path.exists():
        raise RobotFileError(f"no robot named {text!r} (known: {', '.join(names())}; or give a .toml path)")
    return path


def load(name_or_path: str | Path, parameters: Mapping[str, float] | None = None) -> Robot:
    """Read a robot by built-in name or file path; ``parameters`` override the file's defaults."""
    path = robot_path(name_or_path)
    data = read_toml(path, "robot file", RobotFileError)
    return _Reader(path, data).robot(parameters or {})


class _Reader:
    """Turns one parsed TOML file into a Robot, naming file and key in every error."""

    def __init__(self, path: Path, data: dict) -> None:
        self.path = path
        self.data = data
        self.names: dict[str, float] = {"pi": math.pi, "deg": math.pi / 180}

    def fail(self, key: str, message: str) -> RobotFileError:
        return RobotFileError(f"{self.path}: {key}: {message}")

    def text(self, key: str, default: str | None = None, choices: tuple[str, ...] | None = None) -> str:
        value = self.data.get(key, default)
        if value is None:
            raise self.fail(key, "missing")
        if not isinstance(value, str):
            raise self.fail(key, f"must be a string, got {value!r}")
        if choices and value not in choices:
            raise self.fail(key, f"{value!r} is not one of {', '.join(choices)}")
        return value

    def number(self, key: str, value: object) -> float:
        """A number, or a string expression of numbers, pi, deg and the parameters."""
        if isinstance(value, bool):
            raise self.fail(key, f"must be a number, got {value!r}")
        if isinstance(value, int | float):
            result = float(value)
        elif isinstance(value, str):
            try:
                result = float(self._evaluate(ast.parse(value, mode="eval").body))
            except SyntaxError:
                raise self.fail(key, f"cannot read {value!r} as a number or an expression") from None
            except KeyError as exc:
                known = ", ".join(self.names)
                raise self.fail(key, f"unknown name {exc.args[0]!r} in {value!r} (known: {known})") from None
            except (ValueError, ZeroDivisionError, OverflowError) as exc:
                raise self.fail(key, f"cannot evaluate {value!r}: {exc}") from None
        else:
            raise self.fail(key, f"must be a number or an expression string, got {value!r}")
        if not math.isfinite(result):
            raise self.fail(key, f"{value!r} is not finite")
        return result

    def _evaluate(self, node: ast.AST) -> float:
        if isinstance(node, ast.Constant) and isinstance(node.value, int | float) and not isinstance(
                node.value, bool):
            return node.value
        if isinstance(node, ast.Name):
            return self.names[node.id]
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            return _OPS[type(node.op)](self._evaluate(node.left), self._evaluate(node.right))
        if isinstance(node, ast.UnaryOp) and type(node.op) in _OPS:
            return _OPS[type(node.op)](self._evaluate(node.operand))
        raise ValueError("only numbers, + - * / **, parentheses, pi, deg and parameter names are allowed")

    def vector(self, key: str, value: object, size: int) -> np.ndarray:
        if not isinstance(value, list) or len(value) != size:
            raise self.fail(key, f"must be a list of {size} numbers, got {value!r}")
        return np.array([self.number(f"{key}[{i}]", v) for i, v in enumerate(value)])

    def pose(self, key: str) -> np.ndarray | None:
        table = self.data.get(key)
        if table is None:
            return None
        if not isinstance(table, dict):
            raise self.fail(key, "must be a table with xyz and euler_zyx")
        unknown = sorted(set(table) - POSE_KEYS)
        if unknown:
            raise self.fail(f"{key}.{unknown[0]}", f"unknown key (expected {', '.join(sorted(POSE_KEYS))})")
        pose = np.eye(4)
        pose[:3, 3] = self.vector(f"{key}.xyz", table.get("xyz", [0, 0, 0]), 3)
        zyx = self.vector(f"{key}.euler_zyx", table.get("euler_zyx", [0, 0, 0]), 3)
        pose[:3, :3] = euler_zyx_to_matrix(zyx)
        return pose

    def parameters(self, overrides: Mapping[str, float]) -> dict[str, float]:
        table = self.data.get("parameters", {})
        if not isinstance(table, dict):
            raise self.fail("parameters", "must be a table of name = number")
        params: dict[str, float] = {}
        for name, value in table.items():
            if not name.isidentifier() or name in self.names:
                raise self.fail(f"parameters.{name}", "must be an identifier other than pi and deg")
            params[name] = self.number(f"parameters.{name}", value)
        for name, value in overrides.items():
            if name not in params:
                known = ", ".join(params) or "none"
                raise RobotFileError(f"{self.path}: robot has no parameter {name!r} (parameters: {known})")
            if not math.isfinite(float(value)):
                raise RobotFileError(f"{self.path}: parameter {name} must be finite, got {value!r}")
            params[name] = float(value)
        self.names.update(params)
        return params

    def robot(self, overrides: Mapping[str, float]) -> Robot:
        unknown = sorted(set(self.data) - TOP_KEYS)
        if unknown:
            raise self.fail(unknown[0], f"unknown key (expected {', '.join(sorted(TOP_KEYS))})")
        name = self.text("name")
        convention = self.text("convention", choices=tuple(CONVENTIONS))
        unit = self.text("length_unit", choices=LENGTH_UNITS)
        closed_form = self.data.get("closed_form")
        if closed_form is not None:
            closed_form = self.text("closed_form", choices=CLOSED_FORMS)
        params = self.parameters(overrides)
        rows = self.data.get("dh")
        if not isinstance(rows, list) or not rows or not all(isinstance(r, dict) for r in rows):
            raise self.fail("dh", "needs one [[dh]] table per DH row")
        columns = ("a", "alpha", "d", "theta", "joint", "lower", "upper", "centre", "name")
        cols: dict[str, list] = {k: [] for k in columns}
        for i, row in enumerate(rows, start=1):
            key = f"dh[{i}]"
            bad = sorted(set(row) - ROW_KEYS)
            if bad:
                raise self.fail(f"{key}.{bad[0]}", f"unknown key (expected {', '.join(sorted(ROW_KEYS))})")
            for col in ("a", "alpha", "d"):
                if col not in row:
                    raise self.fail(f"{key}.{col}", "missing")
                cols[col].append(self.number(f"{key}.{col}", row[col]))
            cols["theta"].append(self.number(f"{key}.theta", row.get("theta", 0)))
            joint = row.get("joint", REVOLUTE)
            if joint not in JOINT_TYPES:
                raise self.fail(f"{key}.joint", f"{joint!r} is not one of {', '.join(JOINT_TYPES)}")
            cols["joint"].append(joint)
            if joint == FIXED and ("lower" in row or "upper" in row):
                raise self.fail(f"{key}.lower", "a fixed row has no joint limits")
            if joint == REVOLUTE:
                lo = self.number(f"{key}.lower", row.get("lower", -math.inf)) if "lower" in row else -math.inf
                hi = self.number(f"{key}.upper", row.get("upper", math.inf)) if "upper" in row else math.inf
                if lo > hi:
                    raise self.fail(f"{key}.lower", f"lower limit {lo:g} is above upper limit {hi:g}")
                cols["lower"].append(lo)
                cols["upper"].append(hi)
            cols["centre"].append(self.vector(f"{key}.centre", row["centre"], 3) if "centre" in row else None)
            cols["name"].append(str(row.get("name", f"row {i}")))
        if cols["joint"].count(REVOLUTE) == 0:
            raise self.fail("dh", "needs at least one revolute row")
        if len(rows) > 32:
            raise self.fail("dh", f"has {len(rows)} rows; at most 32 are supported")
        marked = [c is not None for c in cols["centre"]]
        if any(marked) and not all(marked):
            raise self.fail(f"dh[{marked.index(False) + 1}].centre",
                            "give a centre for every row or for none")
        centres = np.array(cols["centre"]) if all(marked) else None
        try:
            chain = Chain(cols["a"], cols["alpha"], cols["d"], cols["theta"], cols["joint"], convention,
                          self.pose("base"), self.pose("tool"), cols["lower"], cols["upper"])
        except ValueError as exc:
            raise self.fail("dh", str(exc)) from None
        robot = Robot(name=name, title=self.text("title", default=name), source=self.text("source"),
                      path=self.path, convention=convention, length_unit=unit, chain=chain,
                      closed_form=closed_form, parameters=params, centres=centres,
                      row_names=tuple(cols["name"]))
        if closed_form is not None:
            self.check_closed_form(robot)
        return robot

    def check_closed_form(self, robot: Robot) -> None:
        """The closed-form solvers assume a table shape; say which entry breaks it."""
        c = robot.chain
        half_pi = math.pi / 2
        if robot.closed_form == "spatial_rrr":
            shape = "(a1, pi/2, d1, q1), (a2, 0, 0, q2), (a3, 0, 0, q3)"
            alpha, d_zero = (half_pi, 0, 0), (1, 2)
        elif robot.closed_form == "planar_3r":
            shape = "(a1, 0, 0, q1), (a2, 0, 0, q2), (a3, 0, 0, q3)"
            alpha, d_zero = (0, 0, 0), (0, 1, 2)
        else:
            shape = (f"the CRS arm's (0, -pi/2, {crs.BASE_HEIGHT_IN:g}, q1), "
                     f"({crs.UPPER_ARM_IN:g}, 0, 0, q2), ({crs.FOREARM_IN:g}, 0, 0, q3)"
                     " in inches (crslab.crs)")
            alpha, d_zero = (-half_pi, 0, 0), (1, 2)
        where = f"closed_form {robot.closed_form!r} needs a standard DH table {shape} with no offsets"
        if (c.convention != STANDARD or c.n_rows != 3 or c.n_joints != 3 or c.base is not None
                or c.tool is not None):
            raise self.fail("closed_form", where)
        for i in range(3):
            if not math.isclose(c.alpha_rad[i], alpha[i], abs_tol=1e-12):
                raise self.fail(f"dh[{i + 1}].alpha", where)
            if c.theta_rad[i] != 0:
                raise self.fail(f"dh[{i + 1}].theta", where)
            if i in d_zero and c.d[i] != 0:
                raise self.fail(f"dh[{i + 1}].d", where)
        if robot.closed_form == "crs":
            want = (0.0, crs.UPPER_ARM_IN, crs.FOREARM_IN)
            if robot.length_unit != "in" or tuple(c.a) != want or c.d[0] != crs.BASE_HEIGHT_IN:
                raise self.fail("dh", where)
        elif not np.all(c.a[-2:] > 0) or (robot.closed_form == "planar_3r" and not c.a[0] > 0):
            raise self.fail("dh", f"{where} and positive link lengths")


__all__ = ["MODIFIED", "STANDARD", "Robot", "RobotFileError", "load", "names", "robot_path"]
