"""How the framework calls a lab's ``lab()`` and ``printing()``: whatever definition C lets the board
call.

The course framework declares ``lab`` with seven parameters in its own file and calls it through that
declaration; the lab file's definition is compiled apart. On the C28x a definition with fewer
parameters (the six without ``int error``, or none), a K&R-style one or ``void lab()`` without a
prototype runs all the same: each argument travels in a register the function reads or ignores, and
``double`` is ``float`` there, so the K&R promotion changes nothing. WebAssembly checks every call's
signature, and a 64-bit host passes a promoted ``float`` as a ``double``: so crslab calls the lab's
function from the lab's own translation unit, after its definition, where the compiler knows its type
and converts each argument to it. The calls (:func:`calls_source`) are appended to the unit the lab
is compiled in (the WebAssembly build's and the native build's); the firmware calls them
(``crs_lab_call_lab``, ``crs_lab_call_printing``: csrc/firmware/firmware.c).

The definitions are read from the lab's text (comments, strings and preprocessor lines set aside):
how many parameters each takes, whether it is ``static`` (then the framework's file cannot call it,
on the board either: the build says so).

>>> [d.parameters for d in find_definitions("void lab(float a, float b, float c, float *t1, "
...                                         "float *t2, float *t3) { }", "lab")]
[6]
>>> d = find_definitions("void lab(a, b, c, t1, t2, t3, e)\\nfloat a, b, c; float *t1, *t2, *t3;"
...                      " int e;\\n{ }", "lab")[0]
>>> d.parameters, d.knr
(7, True)
>>> find_definitions("void lab(void);\\nvoid lab(void) { }", "lab")[0].parameters
0
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from crslab.lab.variables import _without_preprocessor, strip_comments

LAB_ARGUMENTS = ("theta1motor", "theta2motor", "theta3motor", "tau1", "tau2", "tau3", "error")
"""What the framework passes to ``lab()``, in order."""
CALLS_UNIT = "crslab-calls"
"""The name the calls' lines go by in the compiler's messages."""
CALL_LAB = "crs_lab_call_lab"
CALL_PRINTING = "crs_lab_call_printing"


class EntryPointError(ValueError):
    """The lab defines ``lab()`` or ``printing()`` in a way the framework cannot call (one line)."""


@dataclass(frozen=True)
class Definition:
    """One function definition (or, with ``declared_only``, a declaration) in a lab's text."""

    name: str
    parameters: int
    knr: bool
    static: bool
    line: int
    declared_only: bool = False


def _parameter_count(params: str) -> int:
    params = params.strip()
    if not params or re.fullmatch(r"void", params):
        return 0
    depth, count = 0, 1
    for ch in params:
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        elif ch == "," and depth == 0:
            count += 1
    return count


def _closing(code: str, i: int, open_: str, close: str) -> int:
    depth = 0
    for j in range(i, len(code)):
        if code[j] == open_:
            depth += 1
        elif code[j] == close:
            depth -= 1
            if depth == 0:
                return j
    return -1


def find_definitions(text: str, name: str) -> list[Definition]:
    """The file-scope definitions of function ``name`` in ``text`` (then its declarations, marked
    ``declared_only``), in file order."""
    code = _without_preprocessor(strip_comments(text, literals=True))
    depth, defined, declared = 0, [], []
    pattern = re.compile(rf"\b{re.escape(name)}\s*\(")
    i = 0
    while i < len(code):
        ch = code[i]
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        elif depth == 0 and ch == name[0] and (m := pattern.match(code, i)) and (i == 0 or not (
                code[i - 1].isalnum() or code[i - 1] == "_")):
            open_ = m.end() - 1
            close = _closing(code, open_, "(", ")")
            if close < 0:
                break
            start = max(code.rfind(";", 0, i), code.rfind("}", 0, i)) + 1
            head = code[start:i]
            after = code[close + 1:]
            rest = after.lstrip()
            line = code.count("\n", 0, i) + 1
            static = re.search(r"\bstatic\b", head) is not None
            count = _parameter_count(code[open_ + 1:close])
            if "typedef" in head or head.rstrip().endswith(("(", "*")):
                pass  # a type, or a pointer to a function
            elif rest.startswith("{"):
                defined.append(Definition(name, count, False, static, line))
            elif rest.startswith(";") or rest.startswith(","):
                declared.append(Definition(name, count, False, static, line, declared_only=True))
            else:  # K&R: the parameters' declarations, then the body
                body = after.find("{")
                if body >= 0 and re.fullmatch(r"[\w\s,*\[\]();]*", after[:body]):
                    defined.append(Definition(name, count, True, static, line))
            i = close + 1
            continue
        i += 1
    return defined + declared


def lab_definition(text: str) -> Definition | None:
    """How ``text`` defines ``lab()`` (None: it does not).
    Raises :class:`EntryPointError` when the framework cannot call it.

    >>> lab_definition("static void lab(void) { }")
    Traceback (most recent call last):
    ...
    crslab.lab.entry_points.EntryPointError: lab() is static (line 1), so the framework's file cannot call \
it (the board's linker does not find it either): remove `static`
    """
    return _callable(text, "lab", len(LAB_ARGUMENTS), "the framework passes 7: theta1motor, theta2motor, "
                     "theta3motor, tau1, tau2, tau3, error")


def printing_definition(text: str) -> Definition | None:
    """How ``text`` defines ``printing()``, as :func:`lab_definition`."""
    return _callable(text, "printing", 0, "the framework calls it with none")


def _callable(text: str, name: str, most: int, passes: str) -> Definition | None:
    found = [d for d in find_definitions(text, name) if not d.declared_only]
    if not found:
        return None
    d = found[0]
    if d.static:
        raise EntryPointError(f"{name}() is static (line {d.line}), so the framework's file cannot call it "
                              "(the board's linker does not find it either): remove `static`")
    if d.parameters > most:
        raise EntryPointError(f"{name}() takes {d.parameters} parameters (line {d.line}); {passes}")
    return d


def calls_source(lab: Definition | None, printing: Definition | None) -> str:
    """The calls appended to the lab's translation unit: the framework's seven arguments passed to
    ``lab()`` as it is defined (its first ``parameters``), ``printing()`` with none. Nothing for a
    function the lab does not define.

    >>> print(calls_source(Definition("lab", 6, False, False, 3), None))
    #line 1 "crslab-calls"
    void crs_lab_call_lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2, \
float *tau3, int error);
    void crs_lab_call_lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2, \
float *tau3, int error)
    { (void)error; lab(theta1motor, theta2motor, theta3motor, tau1, tau2, tau3); }
    <BLANKLINE>
    """
    lines = [f'#line 1 "{CALLS_UNIT}"']
    if lab is not None:
        head = (f"void {CALL_LAB}(float theta1motor, float theta2motor, float theta3motor, float *tau1, "
                "float *tau2, float *tau3, int error)")
        unused = "".join(f"(void){a}; " for a in LAB_ARGUMENTS[lab.parameters:])
        lines += [f"{head};", head, f"{{ {unused}lab({', '.join(LAB_ARGUMENTS[:lab.parameters])}); }}"]
    if printing is not None:
        lines += [f"void {CALL_PRINTING}(void);", f"void {CALL_PRINTING}(void) {{ printing(); }}"]
    return "\n".join([*lines, ""]) if len(lines) > 1 else ""


def entry_calls(text: str) -> str:
    """:func:`calls_source` for a lab's text (its own and the headers of its folder it includes).
    Raises :class:`EntryPointError`."""
    return calls_source(lab_definition(text), printing_definition(text))
