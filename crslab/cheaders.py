"""Read C headers as cffi declarations, so each prototype and constant is written once.

Also loaded by path from ``csrc/cffi_build.py`` at build time: keep it free of crslab imports.

>>> cdef_from_header("#include <x.h>\\nstatic const double L_IN = 10.0; /* in */\\nint f(int a);")
'static const double L_IN; /* in */\\nint f(int a);'
"""

from __future__ import annotations

import re

_STATIC_CONST = re.compile(r"^(\s*static const [\w ]+?\s+\w+)\s*=[^;]*;")


def cdef_from_header(text: str) -> str:
    """Drop preprocessor lines and ``static const`` initialisers from a C header."""
    out = []
    for line in text.splitlines():
        if line.lstrip().startswith("#"):
            continue
        out.append(_STATIC_CONST.sub(r"\1;", line))
    return "\n".join(out)
