"""A lab that asks for printing but defines no ``printing()``: on the board (and in crslab) the
framework then prints nothing, silently. Typically a typo (``printng``, ``Printing``). crslab
knows both halves without reading the lab's mind: the board counts the ticks whose ``lab()``
triggered printing (``print_triggers``: the generation's ``print_call``, ``SWI_post(&SWI_printf)``
in Gen A, ``UARTprint = 1`` in Gen B) and whether the lab defines ``printing``
(``CRS_LAB_HAS_PRINTING``); the lab's text gives the function it probably meant.

>>> from crslab.generations import GEN_A
>>> text = "void printng(void) { }\\nvoid lab(void) { SWI_post(&SWI_printf); }"
>>> print(missing_printing_notice("lab1.c", text, has_printing=False, triggers=40, generation=GEN_A))
... # doctest: +NORMALIZE_WHITESPACE
warning: lab1.c triggered printing 40 times (SWI_post(&SWI_printf)) but defines no printing(),
so nothing was printed, as on the board; did you mean printng() to be printing()?
>>> missing_printing_notice("lab1.c", text, has_printing=True, triggers=40, generation=GEN_A) is None
True
"""

from __future__ import annotations

import difflib
import re

from crslab.generations import Generation

_FUNCTION = re.compile(r"^[ \t]*(?:static\s+)?(?:void|int)\s+(\w+)\s*\(\s*(?:void)?\s*\)\s*\{", re.MULTILINE)


def defined_functions(text: str) -> list[str]:
    """The names of the functions without arguments that ``text`` defines (what ``printing`` is).

    >>> defined_functions("void lab(float a) {}\\nvoid Printing(void)\\n{\\n}\\nint helper() { return 1; }")
    ['Printing', 'helper']
    """
    return _FUNCTION.findall(text)


def missing_printing_notice(lab_name: str, text: str, *, has_printing: bool, triggers: int,
                            generation: Generation) -> str | None:
    """The warning for a lab that triggered printing ``triggers`` times without a ``printing()``."""
    if has_printing or triggers <= 0:
        return None
    how = generation.print_call
    names = [n for n in defined_functions(text) if n not in ("lab", "main")]
    near = difflib.get_close_matches("printing", names, n=1, cutoff=0.6) or [
        n for n in names if n.lower() == "printing"]
    hint = f"; did you mean {near[0]}() to be printing()?" if near else "; define void printing(void)"
    return (f"warning: {lab_name} triggered printing {triggers} times ({how}) but defines no printing(), "
            f"so nothing was printed, as on the board{hint}")
