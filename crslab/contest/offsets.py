"""A lab's own encoder offsets, read from its text and its own headers': the arm's resting pose
on the lab's bench (:func:`contest_rest`, :class:`Rest`).

On the real bench a lab's ``offset_Enc2_rad`` and ``offset_Enc3_rad`` are what its arm's motors 2
and 3 read at rest (Lab 1 calibrates them: docs/first-lab.md), so a contest judged as a TA judges
it starts the arm where the lab was calibrated to find it. C gives a variable at file scope a
constant initialiser: :func:`lab_offsets` evaluates it (numbers, ``+ - * /``, parentheses, casts
to a floating type, object-like ``#define`` names of the lab and of the framework's headers) and
rounds it to a C ``float``, as the board holds it.

>>> lab_offsets('#define PI 3.14159265\\nfloat offset_Enc2_rad = -24.0*PI/180;\\n'
...             'float offset_Enc3_rad = 0.24f;').rad
(-0.41887903213500977, 0.23999999463558197)
>>> lab_offsets('float offset_Enc2_rad = -0.42;').why
'it defines no offset_Enc3_rad'
"""

from __future__ import annotations

import operator
import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

NAMES = ("offset_Enc2_rad", "offset_Enc3_rad")

_TOKEN = re.compile(r"\s*(?:(?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)(?P<suffix>[fFlLuU]*)"
                    r"|(?P<name>[A-Za-z_]\w*)|(?P<op>[-+*/()]))")
_DEFINE = re.compile(r"^[ \t]*#[ \t]*define[ \t]+([A-Za-z_]\w*)[ \t]+(.+?)[ \t]*$", re.MULTILINE)
_CASTS = {"float", "double", "long", "int", "float32", "float64", "Float32"}


class NotConstant(ValueError):
    """An initialiser :func:`evaluate` cannot work out; its text says what stopped it."""


@dataclass(frozen=True)
class LabOffsets:
    """The lab's two offsets (rad, as C floats) or, when they cannot be read, why (``rad`` None)."""

    rad: tuple[float, float] | None
    why: str = ""


def defines(text: str) -> dict[str, str]:
    """The object-like ``#define`` names of a C text and what they stand for (comments removed)."""
    from crslab.lab.variables import strip_comments

    return {name: body for name, body in _DEFINE.findall(strip_comments(text))}


Value = tuple[float, str]
"""A C constant: its value and its type, ``i`` (an integer), ``f`` (float) or ``d`` (double)."""


def evaluate(expr: str, names: dict[str, str], depth: int = 0) -> Value:
    """The value and type of a constant arithmetic expression in C (numbers, ``+ - * /``,
    parentheses, a cast to an arithmetic type), ``names`` standing for the text they are defined
    as; each operation in the type C's usual arithmetic conversions give it (an integer division
    truncates, two floats make a float, rounded as a float).

    >>> evaluate("-(1 + 2) * 3.5f / (float)2", {})
    (-5.25, 'f')
    >>> evaluate("HALF * TWO + 1/2", {"HALF": "0.5", "TWO": "(1 + 1)"})
    (1.0, 'd')
    >>> evaluate("x + 1", {})
    Traceback (most recent call last):
    ...
    crslab.contest.offsets.NotConstant: 'x' is not a constant
    """
    if depth > 16:
        raise NotConstant("#define names nest too deeply")
    tokens: list[tuple[str, str]] = []
    pos = 0
    text = expr.strip()
    while text[pos:].strip():
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            raise NotConstant(f"{text[pos:].strip()[:20]!r} is not arithmetic crslab reads")
        kind = "number" if m.group("number") else m.lastgroup
        tokens.append((kind, m.group(0).strip()))  # type: ignore[arg-type]
        pos = m.end()
    parser = _Parser(tokens, names, depth)
    value = parser.sum()
    if parser.i != len(tokens):
        raise NotConstant(f"{tokens[parser.i][1]!r} is not arithmetic crslab reads")
    return value


def _typed(value: float, kind: str) -> Value:
    return (float(np.float32(value)), "f") if kind == "f" else (value, kind)


_OPS = {"+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv}


def _arith(op: str, a: Value, b: Value) -> Value:
    kind = "d" if "d" in (a[1], b[1]) else "f" if "f" in (a[1], b[1]) else "i"
    x, y = a[0], b[0]
    if op == "/" and y == 0:
        raise NotConstant("a division by zero")
    if kind == "i":
        if op == "/":
            q = abs(int(x)) // abs(int(y))
            return (float(q if (x < 0) == (y < 0) else -q), "i")
        return (float(_OPS[op](x, y)), "i")
    if kind == "f":
        return (float(_OPS[op](np.float32(x), np.float32(y))), "f")
    return (float(_OPS[op](x, y)), "d")


class _Parser:
    def __init__(self, tokens: list[tuple[str, str]], names: dict[str, str], depth: int) -> None:
        self.t, self.names, self.depth, self.i = tokens, names, depth, 0

    def peek(self, ahead: int = 0) -> tuple[str, str]:
        k = self.i + ahead
        return self.t[k] if k < len(self.t) else ("end", "")

    def take(self) -> tuple[str, str]:
        tok = self.peek()
        if tok[0] == "end":
            raise NotConstant("the expression ends early")
        self.i += 1
        return tok

    def sum(self) -> Value:
        v = self.product()
        while self.peek()[1] in ("+", "-"):
            op = self.take()[1]
            v = _arith(op, v, self.product())
        return v

    def product(self) -> Value:
        v = self.unary()
        while self.peek()[1] in ("*", "/"):
            op = self.take()[1]
            v = _arith(op, v, self.unary())
        return v

    def unary(self) -> Value:
        kind, text = self.peek()
        if text in ("+", "-"):
            self.take()
            value, typ = self.unary()
            return (value if text == "+" else -value, typ)
        if text == "(":
            if self.peek(1)[0] == "name" and self.peek(1)[1] in _CASTS and self.peek(2)[1] == ")":
                cast = self.peek(1)[1]
                self.i += 3
                value, _ = self.unary()
                return _typed(float(int(value)) if cast in ("int", "long") else value,
                              "i" if cast in ("int", "long") else "f" if "32" in cast or cast == "float"
                              else "d")
            self.take()
            v = self.sum()
            if self.take()[1] != ")":
                raise NotConstant("a parenthesis is not closed")
            return v
        kind, text = self.take()
        if kind == "number":
            digits = text.rstrip("fFlLuU")
            suffix = text[len(digits):].lower()
            if not any(c in digits for c in ".eE"):
                return (float(int(digits)), "i") if "f" not in suffix else _typed(float(digits), "f")
            return _typed(float(digits), "f" if "f" in suffix else "d")
        if kind == "name":
            if text not in self.names:
                raise NotConstant(f"{text!r} is not a constant")
            return evaluate(self.names[text], self.names, self.depth + 1)
        raise NotConstant(f"{text!r} is not arithmetic crslab reads")


_INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*[<"]([^>"]+)[>"]', re.MULTILINE)


def header_defines(text: str) -> dict[str, str]:
    """The ``#define`` names of the framework's headers the lab includes (``csrc/firmware/include``,
    e.g. Gen A's ``PI`` in ``coecsl.h``)."""
    from crslab import resources

    folder = resources.path("csrc", "firmware", "include")
    out: dict[str, str] = {}
    for name in _INCLUDE.findall(text):
        base = name.rsplit("/", 1)[-1]
        if (folder / base).is_file():
            out.update(defines((folder / base).read_text(errors="replace")))
    return out


def lab_offsets(text: str) -> LabOffsets:
    """The lab's ``offset_Enc2_rad`` and ``offset_Enc3_rad`` as the board holds them (C floats),
    its own ``#define`` names first, then those of the headers it includes
    (:func:`header_defines`). ``text`` is the lab's with its own headers' before it
    (:func:`crslab.lab.includes.with_own_headers`), where a team may keep its offsets."""
    from crslab.lab.variables import find_variables

    found = {v.name: v for v in find_variables(text) if v.name in NAMES and not v.dims}
    names = {**header_defines(text), **defines(text)}
    out = []
    for name in NAMES:
        v = found.get(name)
        if v is None:
            return LabOffsets(None, f"it defines no {name}")
        if v.initial is None:
            out.append(0.0)  # C zeroes a global without an initialiser
            continue
        try:
            out.append(float(np.float32(evaluate(v.initial, names)[0])))
        except NotConstant as exc:
            return LabOffsets(None, f"{name} = {' '.join(v.initial.split())[:40]}: {exc}")
    return LabOffsets((out[0], out[1]))


@dataclass(frozen=True)
class Rest:
    """Where the arm rests in a contest run (motor angles, rad) and why there: ``lab`` (the lab's
    own ``offset_Enc2_rad``/``offset_Enc3_rad``), ``option`` (``--offsets``) or ``default``
    (crslab's arm, with ``why`` the lab's could not be used)."""

    motor_rad: tuple[float, float, float]
    source: str
    why: str = ""

    def line(self) -> str:
        """The card's line about it.

        >>> print(Rest((0.0, -0.42, 0.24), "option").line())
        rest      -0.4200 0.2400 rad: --offsets
        """
        return f"rest      {self.motor_rad[1]:.4f} {self.motor_rad[2]:.4f} rad: {self.said}"

    @property
    def said(self) -> str:
        """Why the arm rests there, in words."""
        return {"lab": "the lab's own offset_Enc2_rad, offset_Enc3_rad (a lab is calibrated to its bench)",
                "option": "--offsets",
                "default": f"crslab's arm's, since the lab's offsets cannot be used: {self.why}"}[self.source]


def contest_rest(text: str, offsets: Sequence[float] | None = None) -> Rest:
    """The resting pose of a contest run of the lab whose text is ``text``: ``offsets`` (motor
    angles 2 and 3, rad) when given, else the lab's own offsets, else crslab's arm's."""
    from crslab.plant.model_files import REST_MOTOR_RAD

    if offsets:
        return Rest((REST_MOTOR_RAD[0], float(offsets[0]), float(offsets[1])), "option")
    own = lab_offsets(text)
    if own.rad is None:
        return Rest(tuple(REST_MOTOR_RAD), "default", own.why)  # type: ignore[arg-type]
    return Rest((REST_MOTOR_RAD[0], *own.rad), "lab")
