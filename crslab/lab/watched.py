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

from dataclasses import dataclass

from crslab.lab.variables import HOST_TYPES, find_variables


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
        base = HOST_TYPES.get(self.ctype, self.ctype)
        dims = f"[{self.length}]" if self.length is not None else ""
        return f"extern {base} {self.name}{dims};"

    @property
    def is_integer(self) -> bool:
        """True for integer types (values are rounded when written)."""
        return self.ctype not in ("float", "double", "float32", "Float32", "long double", "float64")


def find_watched(source_text: str) -> list[WatchedVar]:
    """Every variable named by a ``DATA_SECTION`` pragma, with its declaration, in file order
    (pointers and ``const`` variables left out: they are not values to watch or set)."""
    return [WatchedVar(v.name, v.ctype, v.length, v.initial, v.section, v.line)
            for v in find_variables(source_text) if v.section is not None and not v.pointer and not v.const]
