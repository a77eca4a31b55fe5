"""Where a lab's globals live in the F28335's data memory, as the TI linker lays them out.

The C28x addresses 16-bit words: a ``char`` and an ``int`` take one word, a ``long``, a ``float``
(and a ``double``, 32 bits under the course's COFF ABI) and a pointer two, a ``long long`` and a
``long double`` four; anything of two words or more starts at an even address. The linker puts
each section of the lab's object file at the section's origin on page 1 (the generation's
``section_origins``: ``.my_arrs`` and ``.my_vars`` for the ``#pragma DATA_SECTION`` variables,
``.ebss`` for every other global, ``.econst`` for ``const`` ones right after it), the variables in
the order the file defines them, then the framework's own variables of that section (Simulink's
``SIMU_Var1..7_fromSIMU_16bit`` in ``.ebss``; ``matlabLock`` in ``.my_vars`` where MATLAB reads set
it, Gen A's), in the generation's own object file (``framework_object``). A section
that grows past the next one's origin pushes it up; a section of another name goes after the last.
The same file always gets the same addresses (:func:`layout` depends on its text alone).

The board's MATLAB code reads and writes these words (csrc/board/c28x_memory.c); the map
(:mod:`crslab.host_tools.linker_map`) lists them for the course's scripts.

>>> from crslab.generations import GEN_A
>>> from crslab.lab.variables import find_variables
>>> src = '''#pragma DATA_SECTION(whattoprint, ".my_vars")
... float whattoprint = 0;
... #pragma DATA_SECTION(theta1array, ".my_arrs")
... float theta1array[100];
... int mode; long mycount;'''
>>> mem = layout(find_variables(src), GEN_A, "lab1")
>>> [(v.name, f"{v.address:08x}", v.words) for v in mem.variables][:4]
[('mode', '00009000', 1), ('mycount', '00009002', 2), ('SIMU_Var1_fromSIMU_16bit', '00009004', 1), \
('SIMU_Var2_fromSIMU_16bit', '00009005', 1)]
>>> [(v.name, f"{v.address:08x}") for v in mem.variables][-3:]
[('theta1array', '0000c4c0'), ('whattoprint', '0000c816'), ('matlabLock', '0000c818')]
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from crslab.framework_facts import SIMULINK_INPUTS
from crslab.generations import Generation
from crslab.lab.variables import FRAMEWORK_TYPES, LabVariable

PAGE = 1
"""Data memory is page 1 of the C28x's map."""

_C28X = {  # C type -> (words per element, kind)
    "char": (1, "signed"), "signed char": (1, "signed"), "unsigned char": (1, "unsigned"),
    "short": (1, "signed"), "unsigned short": (1, "unsigned"), "int": (1, "signed"),
    "unsigned int": (1, "unsigned"), "long": (2, "signed"), "unsigned long": (2, "unsigned"),
    "long long": (4, "signed"), "unsigned long long": (4, "unsigned"), "float": (2, "float"),
    "double": (2, "float"), "long double": (4, "float"), "_Bool": (1, "bool"), "bool": (1, "bool"),
}
KINDS = ("signed", "unsigned", "float", "bool", "opaque")
"""How a variable's words are made from its value (csrc/board/board.h: ``CRS_MEM_*``, same order)."""

SIMULINK_INPUT_NAMES = tuple(f"SIMU_Var{i}_fromSIMU_16bit" for i in range(1, SIMULINK_INPUTS + 1))
"""The framework's globals that hold what Simulink sent (int: one word each)."""


def c28x_type(ctype: str, pointer: bool = False) -> tuple[int, str]:
    """``(words per element, kind)`` of a C type on the C28x; None's kind for an unknown type.

    >>> c28x_type("int"), c28x_type("Uint32"), c28x_type("double"), c28x_type("float", pointer=True)
    ((1, 'signed'), (2, 'unsigned'), (2, 'float'), (2, 'opaque'))
    """
    if pointer:
        return 2, "opaque"
    resolved = FRAMEWORK_TYPES.get(ctype, ctype)
    if resolved.endswith("*"):
        return 2, "opaque"
    return _C28X.get(resolved, (1, "opaque"))


@dataclass(frozen=True)
class PlacedVariable:
    """A variable at its address: ``count`` elements of ``element_words`` words each."""

    name: str
    address: int
    count: int
    element_words: int
    kind: str
    section: str
    owner: str
    """The object file that defines it (the lab's, or the framework's)."""
    ctype: str
    host_ctype: str
    is_array: bool
    writable: bool
    is_global: bool
    """False for a ``static``: it takes its place but is in no symbol table."""

    @property
    def words(self) -> int:
        """Words it takes."""
        return self.count * self.element_words


@dataclass(frozen=True)
class Section:
    """An output section: its origin and length (words) and each object file's part of it."""

    name: str
    origin: int
    length: int
    inputs: tuple[tuple[int, int, str], ...]
    """``(origin, length, object file)`` of each input section, in address order."""


@dataclass(frozen=True)
class MemoryLayout:
    """Every data section of a lab and every variable in it, in address order."""

    sections: tuple[Section, ...]
    variables: tuple[PlacedVariable, ...]

    def find(self, name: str) -> PlacedVariable | None:
        """The variable called ``name`` (global or static), or None."""
        return next((v for v in self.variables if v.name == name), None)

    def symbols(self) -> list[PlacedVariable]:
        """The variables in the map's symbol tables (not the statics), in address order."""
        return [v for v in self.variables if v.is_global]


def _framework_variables(generation: Generation, defined: set[str]) -> list[LabVariable]:
    """The framework's own variables a lab sees in the map (those the lab does not define)."""
    out = [LabVariable(name, "int", (), False, False, False, None, None, 0)
           for name in SIMULINK_INPUT_NAMES if name not in defined]
    if generation.matlab_lock and "matlabLock" not in defined:
        out.append(LabVariable("matlabLock", "float", (), False, False, False, ".my_vars", None, 0))
    return out


def _section_of(v: LabVariable) -> str:
    return v.section or (".econst" if v.const else ".ebss")


def _even(address: int) -> int:
    return address + (address & 1)


def layout(variables: Iterable[LabVariable], generation: Generation, lab_name: str) -> MemoryLayout:
    """Lay out the globals of the lab ``lab_name`` (its file's stem) for ``generation``."""
    lab_vars = list(variables)
    objects = [(f"{lab_name}.obj", lab_vars),  # the lab's object first, as on the link line
               (generation.framework_object, _framework_variables(generation, {v.name for v in lab_vars}))]
    origins = dict(generation.section_origins)
    order = sorted(origins, key=origins.__getitem__)
    order.insert(order.index(".ebss") + 1, ".econst")
    for _, vs in objects:
        order += [s for s in dict.fromkeys(map(_section_of, vs)) if s not in order]

    sections: list[Section] = []
    placed: list[PlacedVariable] = []
    cursor = 0
    for name in order:
        start = address = _even(max(origins.get(name, cursor), cursor))
        inputs = []
        for owner, vs in objects:
            members = [v for v in vs if _section_of(v) == name]
            if not members:
                continue
            address = part = _even(address)
            for v in members:
                words, kind = c28x_type(v.ctype, v.pointer)
                if words >= 2:
                    address = _even(address)
                placed.append(PlacedVariable(v.name, address, v.length or 1, words, kind, name, owner,
                                             v.ctype, v.host_ctype, bool(v.dims), not v.const, not v.static))
                address += (v.length or 1) * words
            inputs.append((part, address - part, owner))
        if inputs:
            sections.append(Section(name, start, address - start, tuple(inputs)))
            cursor = address
    placed.sort(key=lambda v: v.address)
    return MemoryLayout(tuple(sections), tuple(placed))


def overlapping(layout_: MemoryLayout) -> list[tuple[str, str]]:
    """Pairs of variables whose words overlap (none, for any layout :func:`layout` makes).

    >>> from crslab.generations import GEN_B
    >>> overlapping(layout([], GEN_B, "x"))
    []
    """
    out = []
    vs: Sequence[PlacedVariable] = layout_.variables
    for a, b in zip(vs, vs[1:]):
        if a.address + a.words > b.address:
            out.append((a.name, b.name))
    return out
