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

import math
from collections.abc import Iterable
from dataclasses import dataclass

from crslab.lab.variables import HOST_TYPES, LabVariable, find_variables, wasm_element_type


class WatchedError(ValueError):
    """A use of a watched variable that the lab does not allow. ``key`` names what is wrong as a
    scenario file names it (``var``, ``index`` or ``value``); the message says why, naming the lab."""

    def __init__(self, key: str, message: str) -> None:
        super().__init__(message)
        self.key = key


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
    def is_integer(self) -> bool:
        """True for integer types (values are rounded when written)."""
        return self.ctype not in ("float", "double", "float32", "Float32", "long double", "float64")

    @property
    def integer_range(self) -> tuple[int, int] | None:
        """The values its integer type holds on the board, None for a floating-point type. The widths
        are the C28x's, which the WebAssembly firmware compiles the lab with (``int`` 16 bits,
        ``long`` 32); a native build's ``int`` holds them too.

        >>> [WatchedVar(n, t, None, None, ".my_vars", 1).integer_range for n, t in
        ...  [("a", "long"), ("b", "Uint16"), ("c", "_Bool"), ("d", "float")]]
        [(-2147483648, 2147483647), (0, 65535), (0, 1), None]
        """
        if not self.is_integer:
            return None
        if HOST_TYPES.get(self.ctype, self.ctype) in ("_Bool", "bool"):
            return 0, 1
        fixed = wasm_element_type(self.ctype) or "int32_t"
        bits = int(fixed.removeprefix("u").removeprefix("int").removesuffix("_t"))
        if fixed.startswith("u"):
            return 0, (1 << bits) - 1
        return -(1 << (bits - 1)), (1 << (bits - 1)) - 1

    def check_value(self, value: float, lab: str) -> None:
        """Refuse a value its type cannot hold (an integer's is rounded first), naming ``lab``.

        >>> WatchedVar("mode", "int", None, None, ".my_vars", 1).check_value(3e9, "lab.c")
        Traceback (most recent call last):
        ...
        crslab.lab.watched.WatchedError: 3e+09 does not fit mode, int in lab.c (-32768 to 32767)
        """
        limits = self.integer_range
        if limits is not None and not (math.isfinite(value) and limits[0] <= round(value) <= limits[1]):
            raise WatchedError("value", f"{value:g} does not fit {self.name}, {self.ctype} in {lab} "
                                        f"({limits[0]} to {limits[1]})")


def find_watched(source_text: str) -> list[WatchedVar]:
    """Every variable named by a ``DATA_SECTION`` pragma, with its declaration, in file order
    (pointers and ``const`` variables left out: they are not values to watch or set)."""
    return watched_of(find_variables(source_text))


def watched_of(variables: Iterable[LabVariable]) -> list[WatchedVar]:
    """:func:`find_watched` of a file whose globals were found already (``variables``)."""
    return [WatchedVar(v.name, v.ctype, v.length, v.initial, v.section, v.line)
            for v in variables if v.section is not None and not v.pointer and not v.const]


def watched_var(watched: Iterable[WatchedVar], name: str, index: int | None, lab: str, *,
                whole: bool = False) -> WatchedVar:
    """The watched variable ``name`` of ``lab``, its ``index`` checked: given exactly when it is an
    array (an array may go without one when ``whole``: all of it) and within it. The one check of a
    name and an index, for scenario files, sweeps, the typed commands and the worker alike.

    >>> gains = [WatchedVar("gains", "float", 2, None, ".my_arrs", 3)]
    >>> watched_var(gains, "gains", 1, "pd.c").length
    2
    >>> watched_var(gains, "gains", None, "pd.c")
    Traceback (most recent call last):
    ...
    crslab.lab.watched.WatchedError: gains has 2 elements in pd.c: give an index 0..1
    >>> watched_var(gains, "Kp", None, "pd.c")
    Traceback (most recent call last):
    ...
    crslab.lab.watched.WatchedError: Kp is not a watched (#pragma DATA_SECTION) variable of pd.c ...
    """
    by_name = {v.name: v for v in watched}
    var = by_name.get(name)
    if var is None:
        known = ", ".join(by_name) or "none"
        raise WatchedError("var", f"{name} is not a watched (#pragma DATA_SECTION) variable of {lab} "
                                  f"(watched: {known})")
    if var.length is None and index is not None:
        raise WatchedError("index", f"{name} is not an array in {lab}")
    missing = index is None and not whole
    if var.length is not None and (missing or index is not None and not 0 <= index < var.length):
        raise WatchedError("index", f"{name} has {var.length} elements in {lab}: give an index "
                                    f"0..{var.length - 1}")
    return var
