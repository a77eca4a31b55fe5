"""C89 habits that the board's compiler builds and newer C compilers refuse.

TI's C28x compiler (C89/C99, relaxed) warns and builds a lab that calls a function it has not
declared (``malloc`` without ``<stdlib.h>``, its own function before defining it), declares
something without a type (implicit ``int``), or stores an integer in a pointer or a pointer in a
pointer of another type. clang 16 and gcc 14 made each an error; crslab builds the lab's own
translation unit with each turned back into a warning (:func:`lab_flags`), for the WebAssembly and
the native builds alike, and says for each what the board does (:func:`habit_warnings`).

What such a call returns on the board is another matter: the caller takes an undeclared function to
return an ``int``, which the C28x returns in the accumulator's low half AL, while ``malloc`` returns
its pointer in XAR4 (TI's calling convention: docs/framework.md section 9), so the caller stores
whatever AL held, not the pointer. crslab's WebAssembly build, compiled with the board's widths,
takes the same 16-bit int and stops the run where the lab uses it as a pointer; a native build
(the host's compiler knows ``malloc``'s real type) runs the lab with the real pointer. The C28x
check (:mod:`crslab.lab.c28x_check`) says where the board's pointer is lost.

>>> text = ("lab.c:5:25: warning: call to undeclared library function 'malloc' with type 'void *(unsigned "
...         "long)'; ISO C99 and later do not support implicit function declarations "
...         "[-Wimplicit-function-declaration]\\n")
>>> print(habit_warnings(text)[0])  # doctest: +NORMALIZE_WHITESPACE
lab.c:5: malloc() is called with no declaration before it (C89 allows it: the board's compiler warns
and builds); the board then reads a 16-bit int from AL, where the C28x returns an int, while malloc()
returns its pointer in XAR4: the pointer is lost: #include <stdlib.h>
"""

from __future__ import annotations

import re

HABITS = ("implicit-function-declaration", "implicit-int", "int-conversion", "incompatible-pointer-types")
"""The diagnostics C89 allows and newer compilers make errors (gcc and clang name them alike)."""
CLANG_ONLY = ("incompatible-function-pointer-types",)
"""clang's error for a function pointer of another type (gcc counts it as incompatible-pointer-types)."""
POINTER_RETURNING = {"malloc": "<stdlib.h>", "calloc": "<stdlib.h>", "realloc": "<stdlib.h>",
                     "strcpy": "<string.h>", "strcat": "<string.h>", "strchr": "<string.h>",
                     "strstr": "<string.h>", "memcpy": "<string.h>", "memset": "<string.h>",
                     "memmove": "<string.h>", "getenv": "<stdlib.h>"}
"""C library functions that return a pointer, with the header that declares them."""


def lab_flags(family: str) -> list[str]:
    """The flags the lab's translation unit is compiled with so the habits build as warnings, for a
    compiler of ``family`` (``clang``: only these warnings are shown; ``gcc``: its few default ones,
    of which crslab keeps these).

    >>> lab_flags("gcc")[:1]
    ['-Wno-error=implicit-function-declaration']
    >>> "-Wno-everything" in lab_flags("clang")
    True
    """
    names = [*HABITS, *(CLANG_ONLY if family == "clang" else ())]
    demoted = [f"-Wno-error={n}" for n in names]
    if family == "clang":
        return ["-Wno-everything", *(f"-W{n}" for n in names), *demoted]
    return demoted


_WARNING = re.compile(r"^(?P<file>[^\n]+?):(?P<line>\d+):\d+: warning: (?P<message>[^\n]*?) "
                      r"\[-W(?P<flag>[\w-]+)\]$", re.MULTILINE)
_NAME = re.compile(r"[‘'](\w+)[’']")


def _what(flag: str, message: str) -> str | None:
    if flag == "implicit-function-declaration":
        name = _NAME.search(message)
        if name is None:
            return None
        fn = name.group(1)
        said = (f"{fn}() is called with no declaration before it (C89 allows it: the board's compiler warns "
                "and builds)")
        if fn in POINTER_RETURNING:
            return (f"{said}; the board then reads a 16-bit int from AL, where the C28x returns an int, "
                    f"while {fn}() returns its pointer in XAR4: the pointer is lost: "
                    f"#include {POINTER_RETURNING[fn]}")
        return f"{said}; it is taken to return an int: declare it before the call"
    if flag == "implicit-int":
        return ("a declaration without a type, which C89 makes an int (16 bits on the board and in crslab's "
                "WebAssembly build, 32 in a native one): the board's compiler warns and builds")
    if flag == "int-conversion":
        return ("an integer and a pointer converted into each other without a cast (the board's compiler "
                "warns and builds; on the C28x an int is 16 bits and a pointer 32)")
    if flag in ("incompatible-pointer-types", "incompatible-function-pointer-types"):
        return ("a pointer stored in a pointer to another type (the board's compiler warns and builds; "
                "what it points to is then read as the other type)")
    return None


def habit_warnings(diagnostics: str) -> list[str]:
    """One line per C89 habit in a successful compile's messages (``file:line: what the board does``),
    in order, once per line and kind; the compiler's other warnings are left out.

    >>> habit_warnings("l.c:3:8: warning: type defaults to ‘int’ in declaration of ‘x’ [-Wimplicit-int]\\n"
    ...                "l.c:4:1: warning: unused variable 'y' [-Wunused-variable]\\n")[0][:40]
    'l.c:3: a declaration without a type, whi'
    """
    out: list[str] = []
    for m in _WARNING.finditer(diagnostics):
        what = _what(m["flag"], m["message"])
        if what is None or m["file"].startswith("crslab-"):  # crslab's own lines of the unit
            continue
        line = f"{m['file']}:{m['line']}: {what}"
        if line not in out:
            out.append(line)
    return out
