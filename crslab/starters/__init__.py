"""``crslab new``: a starting file for each of the course's four labs, in each framework
generation, with the structure of the course's own template (the offsets, ``mycount``, watched
variables, printing from ``printing()``, the Simulink PlotVars, the generation's includes). The
files are crslab's own; what differs between generations is filled into ``labN.c.tmpl`` from the
generation's row (:mod:`crslab.generations`): its includes (``starter_includes``), and what its
print trigger asks of the file:

- ``SWI_post(&SWI_printf)`` (Gen A, DSP/BIOS): the call, nothing else.
- ``UARTprint`` (Gen B, C2000Ware, no operating system): the file defines ``int UARTprint`` and
  sets it to 1 to print; its ``main()`` calls the framework's ``mains_code()``.

>>> text = starter_text("lab2", "B")
>>> '#include "F28335Serial.h"' in text, "UARTprint = 1;" in text, "SWI_post" in text
(True, True, False)
>>> print(starter_text("lab1", "A").splitlines()[0])
/* Lab 1 (kinematics): a starting file for the Gen A "CRSRobot" framework, from 'crslab new'.
"""

from __future__ import annotations

from importlib import resources

from crslab._bindings import constants
from crslab.generations import named

LABS = {"lab1": "Lab 1 (kinematics)", "lab2": "Lab 2 (PD control)", "lab3": "Lab 3 (friction compensation)",
        "lab4": "Lab 4 (task-space control)",
        "final": "the final project (the contest: peg, obstacle, groove, egg)"}

_BY_TRIGGER = {  # print trigger -> what the file declares, how lab() asks to print, its main()
    constants.CRS_PRINT_SWI_POST: (
        "", "SWI_post(&SWI_printf);   /* printing() runs once, after lab() returns */", ""),
    constants.CRS_PRINT_UARTPRINT: (
        "int UARTprint = 0;   /* set to 1 in lab(): printing() runs once, after lab() */\n",
        "UARTprint = 1;   /* printing() runs once, after lab() returns */",
        "\nvoid main(void)\n{\n    mains_code();   /* the framework: lab() every 1 ms */\n}\n"),
}


def starter_text(lab: str, generation: str) -> str:
    """The starting file of ``lab`` (``lab1`` .. ``lab4``, ``final``) for the generation named ``generation``
    (``A``, ``B``: :class:`crslab.generations.UnknownGeneration` for another)."""
    if lab not in LABS:
        raise ValueError(f"no such lab {lab!r}: one of {', '.join(LABS)}")
    gen = named(generation)
    globals_, print_call, main = _BY_TRIGGER[gen.print_trigger]
    template = resources.files(__package__).joinpath(f"{lab}.c.tmpl").read_text()
    header = f"/* {LABS[lab]}: a starting file for {gen.title}, from 'crslab new'."
    text = (template.replace("/*@HEADER@*/", header)
            .replace("/*@INCLUDES@*/", gen.starter_includes)
            .replace("/*@GLOBALS@*/\n", globals_)
            .replace("/*@PRINT@*/", print_call)
            .replace("/*@MAIN@*/\n", main))
    assert "/*@" not in text, f"{lab}.c.tmpl has a marker starter_text does not fill"
    return text
