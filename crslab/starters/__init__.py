"""``crslab new``: a starting file for each of the course's four labs, in either framework
generation, with the structure of the course's own template (the offsets, ``mycount``, watched
variables, printing from ``printing()``, the Simulink PlotVars, the generation's includes). The
files are crslab's own; what differs between generations is filled into ``labN.c.tmpl``:

- Gen A ("CRSRobot", DSP/BIOS): ``tistdtypes.h``, ``coecsl.h``, ``user_includes.h``; printing is
  triggered by ``SWI_post(&SWI_printf)``.
- Gen B ("me446 starter", C2000Ware): ``F28335Serial.h``; the file defines PI, TWOPI, HALFPI, GRAV
  and ``int UARTprint`` itself and sets ``UARTprint = 1`` to print; ``main()`` calls the
  framework's ``mains_code()``.

>>> text = starter_text("lab2", "B")
>>> '#include "F28335Serial.h"' in text, "UARTprint = 1;" in text, "SWI_post" in text
(True, True, False)
>>> print(starter_text("lab1", "A").splitlines()[0])
/* Lab 1 (kinematics): a starting file for the Gen A "CRSRobot" framework, from 'crslab new'.
"""

from __future__ import annotations

from importlib import resources

LABS = {"lab1": "Lab 1 (kinematics)", "lab2": "Lab 2 (PD control)", "lab3": "Lab 3 (friction compensation)",
        "lab4": "Lab 4 (task-space control)"}
GENERATIONS = {"A": 'the Gen A "CRSRobot" framework', "B": 'the Gen B "me446 starter" framework'}

_INCLUDES = {
    "A": '#include <tistdtypes.h>\n#include <coecsl.h>\n#include "user_includes.h"\n#include "math.h"',
    "B": ('#include "math.h"\n#include "F28335Serial.h"\n\n'
          "#define PI 3.1415926535897932384626433832795\n"
          "#define TWOPI 6.283185307179586476925286766559\n"
          "#define HALFPI 1.5707963267948966192313216916398\n"
          "#define GRAV 9.81"),
}
_GLOBALS = {"A": "", "B": "int UARTprint = 0;   /* set to 1 in lab(): printing() runs once, after lab() */\n"}
_PRINT = {"A": "SWI_post(&SWI_printf);   /* printing() runs once, after lab() returns */",
          "B": "UARTprint = 1;   /* printing() runs once, after lab() returns */"}
_MAIN = {"A": "",
         "B": "\nvoid main(void)\n{\n    mains_code();   /* the framework: lab() every 1 ms */\n}\n"}


def starter_text(lab: str, generation: str) -> str:
    """The starting file of ``lab`` (``lab1`` .. ``lab4``) for ``generation`` (``A`` or ``B``)."""
    if lab not in LABS:
        raise ValueError(f"no such lab {lab!r}: one of {', '.join(LABS)}")
    if generation not in GENERATIONS:
        raise ValueError(f"no such generation {generation!r}: A or B")
    template = resources.files(__package__).joinpath(f"{lab}.c.tmpl").read_text()
    header = f"/* {LABS[lab]}: a starting file for {GENERATIONS[generation]}, from 'crslab new'."
    text = (template.replace("/*@HEADER@*/", header)
            .replace("/*@INCLUDES@*/", _INCLUDES[generation])
            .replace("/*@GLOBALS@*/\n", _GLOBALS[generation])
            .replace("/*@PRINT@*/", _PRINT[generation])
            .replace("/*@MAIN@*/\n", _MAIN[generation]))
    assert "/*@" not in text, f"{lab}.c.tmpl has a marker starter_text does not fill"
    return text
