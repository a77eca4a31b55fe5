"""The course framework's generations, one row each, read through cffi from the table the board
and the firmware are built with (``csrc/port/generations.c``; ``generations.h`` says what each
field is): a lab's includes say which row it was written for, and everything that differs between
generations is a field of its row, never a comparison with one of them.

>>> [g.name for g in GENERATIONS]
['A', 'B']
>>> of(GEN_B.id).printf_buffer_chars, GEN_A.tx_ring_chars, GEN_B.default_motor_board
(136, 2048, 'piccolo')
>>> detect('#include "F28335Serial.h"').name, detect("#include <coecsl.h>").name
('B', 'A')
>>> of(7)
Traceback (most recent call last):
...
crslab.generations.UnknownGeneration: crslab knows no framework generation 7 (it knows A (1), B (2))
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from crslab._bindings import constants, generation_rows
from crslab.framework_facts import MOTOR_BOARDS


class UnknownGeneration(ValueError):
    """No row of the table has this id or name; the message lists the rows."""


@dataclass(frozen=True)
class Generation:
    """One row of ``csrc/port/generations.c`` (the fields of ``crs_generation``, generations.h)."""

    id: int
    """What the board's ``crs_board.generation`` holds."""
    name: str
    """``A``, ``B``: ``crslab new --gen``, messages."""
    title: str
    include: str
    """The header whose ``#include`` says a lab was written for this generation."""
    starter_includes: str
    """The lines a starting file (``crslab new``) of this generation begins with."""
    formatter: int
    """``CRS_FORMATTER_*``: how serial_printf turns numbers into text."""
    print_trigger: int
    """``CRS_PRINT_*``: what makes the framework call ``printing()``."""
    printf_buffer_chars: int
    """serial_printf's buffer, the terminating NUL included: a line this long or longer overflows it."""
    tx_ring_chars: int
    """SerialA's transmit ring (the SCI's FIFO and shift register come on top)."""
    scib_tx_ring_chars: int
    scic_tx_ring_chars: int
    matlab: int
    """``CRS_MATLAB_*`` bits: what its SerialC code does besides reads and writes."""
    default_motor_board: str
    """The motor board of its era's hardware (a name of ``framework_facts.MOTOR_BOARDS``)."""
    framework_object: str
    """The framework's object file holding its variables, as the map names it."""
    map_folder: str
    """Where the course's MATLAB scripts look for the map."""
    section_origins: dict[str, int]
    """Where the linker puts each data section of a lab (16-bit-word addresses on page 1)."""

    @property
    def print_call(self) -> str:
        """What a lab writes in ``lab()`` to have ``printing()`` called.

        >>> GEN_A.print_call, GEN_B.print_call
        ('SWI_post(&SWI_printf)', 'UARTprint = 1')
        """
        return _PRINT_CALLS[self.print_trigger]

    @property
    def matlab_lock(self) -> bool:
        """Every MATLAB read sets the framework's ``matlabLock`` (a float in ``.my_vars``)."""
        return bool(self.matlab & constants.CRS_MATLAB_LOCK)


_PRINT_CALLS = {constants.CRS_PRINT_SWI_POST: "SWI_post(&SWI_printf)",
                constants.CRS_PRINT_UARTPRINT: "UARTprint = 1"}
_BOARD_NAMES = {number: name for name, number in MOTOR_BOARDS.items()}


def _row(r: dict[str, Any]) -> Generation:
    return Generation(
        id=r["id"], name=r["name"], title=r["title"], include=r["include"],
        starter_includes=r["starter_includes"], formatter=r["formatter"], print_trigger=r["print_trigger"],
        printf_buffer_chars=r["printf_buffer_chars"], tx_ring_chars=r["tx_ring_chars"],
        scib_tx_ring_chars=r["scib_tx_ring_chars"], scic_tx_ring_chars=r["scic_tx_ring_chars"],
        matlab=r["matlab"], default_motor_board=_BOARD_NAMES[r["motor_board"]],
        framework_object=r["framework_object"], map_folder=r["map_folder"],
        section_origins={".ebss": r["ebss_origin"], ".my_vars": r["my_vars_origin"],
                         ".my_arrs": r["my_arrs_origin"]})


GENERATIONS: tuple[Generation, ...] = tuple(_row(r) for r in generation_rows())
"""Every row, in the order the course used them."""
GEN_A: Generation = next(g for g in GENERATIONS if g.id == constants.CRS_GEN_A)
"""Gen A, "CRSRobot" (DSP/BIOS): SWI_post(&SWI_printf), the course's small printf."""
GEN_B: Generation = next(g for g in GENERATIONS if g.id == constants.CRS_GEN_B)
"""Gen B, "me446 starter" (C2000Ware): UARTprint, TI's rounding vsprintf."""
NEWEST: Generation = GENERATIONS[-1]
"""The last row: what ``crslab new`` writes unless told otherwise."""


def _known() -> str:
    return ", ".join(f"{g.name} ({g.id})" for g in GENERATIONS)


def of(generation_id: int) -> Generation:
    """The row whose id is ``generation_id``; :class:`UnknownGeneration` when there is none."""
    for g in GENERATIONS:
        if g.id == generation_id:
            return g
    raise UnknownGeneration(f"crslab knows no framework generation {generation_id} (it knows {_known()})")


def named(name: str) -> Generation:
    """The row called ``name`` (``A``, ``B``); :class:`UnknownGeneration` when there is none.

    >>> named("Z")
    Traceback (most recent call last):
    ...
    crslab.generations.UnknownGeneration: crslab knows no framework generation 'Z' (it knows A (1), B (2))
    """
    for g in GENERATIONS:
        if g.name == name:
            return g
    raise UnknownGeneration(f"crslab knows no framework generation {name!r} (it knows {_known()})")


_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.MULTILINE)


def detect(source_text: str) -> Generation:
    """The generation a lab file was written for: the first row whose header it includes; a file
    that includes none of them, the first row's.

    >>> detect('#include <coecsl.h>\\n#include "F28335Serial.h"').name, detect("int x;").name
    ('A', 'A')
    """
    includes = set(_INCLUDE.findall(source_text))
    return next((g for g in GENERATIONS if g.include in includes), GENERATIONS[0])
