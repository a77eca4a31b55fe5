"""The lab's watched variables: those its ``#pragma DATA_SECTION`` lines place in the course's
``.my_vars`` / ``.my_arrs`` sections, which the course's MATLAB tools list, read and write while
the DSP runs (``ME446_serial_ListVars``, ``ME446_serialread``, ``ME446_serialwrite``).

>>> src = '''#pragma DATA_SECTION(whattoprint, ".my_vars")
... float whattoprint = 0.0;
... #pragma DATA_SECTION(theta1array, ".my_arrs")
... float theta1array[100];'''
>>> [(v.name, v.ctype, v.length, v.initial) for v in find_watched(src)]
[('whattoprint', 'float', None, '0.0'), ('theta1array', 'float', 100, None)]
"""

from __future__ import annotations

import re
from dataclasses import dataclass

_PRAGMA = re.compile(r'^\s*#\s*pragma\s+DATA_SECTION\s*\(\s*(\w+)\s*,\s*"([^"]*)"\s*\)', re.MULTILINE)
_TYPES = ("unsigned long", "unsigned int", "unsigned short", "long", "int", "short", "float", "double",
          "Uint16", "Uint32", "Int16", "Int32", "int16", "int32", "float32", "char", "Bool", "bool")
_C_TYPE = {"Uint16": "uint16_t", "Uint32": "uint32_t", "Int16": "int16_t", "Int32": "int32_t",
           "int16": "int16_t", "int32": "int32_t", "float32": "float", "Bool": "unsigned short",
           "bool": "_Bool"}


@dataclass(frozen=True)
class WatchedVar:
    """One watched variable: its name, C type, array length (None: scalar) and initialiser."""

    name: str
    ctype: str
    length: int | None
    initial: str | None
    section: str
    line: int

    @property
    def cdecl(self) -> str:
        """A cffi declaration of the variable, in host types."""
        base = _C_TYPE.get(self.ctype, self.ctype)
        dims = f"[{self.length}]" if self.length is not None else ""
        return f"extern {base} {self.name}{dims};"

    @property
    def is_integer(self) -> bool:
        """True for integer types (values are rounded when written)."""
        return self.ctype not in ("float", "double", "float32")


_DEFINE = re.compile(r"^\s*#\s*define\s+(\w+)\s+(\d+)\s*$", re.MULTILINE)
_SIZE_EXPR = re.compile(r"^[\d\s*+()-]+$")


def _array_length(expr: str, defines: dict[str, str]) -> int | None:
    """An array size such as ``100``, ``N`` or ``3 * MAX_POINTS`` (integer #defines only).

    >>> _array_length("3 * MAX_WP", {"MAX_WP": "20"})
    60
    """
    text = re.sub(r"[A-Za-z_]\w*", lambda m: defines.get(m.group(0), "?"), expr)
    if not _SIZE_EXPR.match(text):
        return None
    return int(eval(text, {"__builtins__": {}}))  # noqa: S307 - digits and + - * ( ) only


def _strip_comments(text: str) -> str:
    text = re.sub(r"/\*.*?\*/", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text, flags=re.DOTALL)
    return re.sub(r"//[^\n]*", "", text)


def find_watched(source_text: str) -> list[WatchedVar]:
    """Every variable named by a ``DATA_SECTION`` pragma, with its declaration, in file order."""
    text = _strip_comments(source_text)
    defines = dict(_DEFINE.findall(text))
    out = []
    type_alt = "|".join(re.escape(t) for t in _TYPES)
    for m in _PRAGMA.finditer(text):
        name, section = m.group(1), m.group(2)
        decl = re.compile(
            rf"^\s*(?:volatile\s+|static\s+)*({type_alt})\s+{re.escape(name)}\s*(\[([^\]]+)\])?"
            rf"\s*(?:=\s*([^;{{]+|\{{[^}}]*\}}))?\s*;", re.MULTILINE)
        d = decl.search(text, m.end())
        if d is None:
            continue
        line = text.count("\n", 0, d.start()) + 1
        length = _array_length(d.group(3), defines) if d.group(3) else None
        if d.group(3) and length is None:
            continue
        initial = d.group(4).strip() if d.group(4) else None
        out.append(WatchedVar(name, d.group(1), length, initial, section, line))
    return out
