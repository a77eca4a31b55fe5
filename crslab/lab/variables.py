"""Every global variable a lab file defines: name, type, array dimensions, section, qualifiers.

The TI linker gives each of them an address in the C28x's data memory, which the course's map
lists and its MATLAB scripts read and write (:mod:`crslab.lab.c28x_memory` lays them out).
A lab file is read as text, not compiled: comments, strings and preprocessor lines are set aside
(integer ``#define`` values are kept for array sizes, ``#pragma DATA_SECTION`` for sections), then
every declaration at file scope is split into its declarators.

Covered: the base types (``char``, ``short``, ``int``, ``long``, ``long long``, ``float``,
``double``, ``long double``, ``_Bool``, with ``signed``/``unsigned``), the framework's type names
(``Uint16``, ``int32``, ``float32``...), the lab's own ``typedef`` of those, pointers, arrays of
any dimension whose sizes are integers, ``#define`` names or arithmetic of them (or ``[]`` with an
initialiser list), ``static``, ``const`` and ``volatile``, several declarators in one declaration.
Left out (they are not variables crslab can lay out): ``extern`` declarations, functions and
function pointers, ``struct``/``union``/``enum`` variables, and declarations inside ``#if 0``.

>>> src = '''#define N 100
... #pragma DATA_SECTION(theta1array, ".my_arrs")
... float theta1array[N];
... float x_in = 0, y_in = 0, *p;   /* three at once */
... static long mycount = 0;
... void lab(float a) { int local = 1; }'''
>>> [(v.name, v.ctype, v.dims, v.pointer, v.static, v.section) for v in find_variables(src)]
[('theta1array', 'float', (100,), False, False, '.my_arrs'), ('x_in', 'float', (), False, False, None), \
('y_in', 'float', (), False, False, None), ('p', 'float', (), True, False, None), \
('mycount', 'long', (), False, True, None)]
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

_PRAGMA = re.compile(r'^\s*#\s*pragma\s+DATA_SECTION\s*\(\s*(\w+)\s*,\s*"([^"]*)"\s*\)', re.MULTILINE)
_DEFINE = re.compile(r"^\s*#\s*define\s+(\w+)\s+\(?\s*(\d+)\s*\)?\s*$", re.MULTILINE)
_SIZE_EXPR = re.compile(r"^[\d\s*+()-]+$")
_KEYWORDS = {"char", "short", "int", "long", "float", "double", "signed", "unsigned", "_Bool", "bool", "void"}
_QUALIFIERS = {"static", "volatile", "const", "register", "extern", "typedef", "inline", "restrict",
               "__restrict", "_Thread_local"}

FRAMEWORK_TYPES = {
    # the framework's headers (csrc/firmware/include) and <stdint.h>: name -> the C type it stands for
    # on the C28x (where char and int are 16 bits, long 32, long double 64)
    "Uint16": "unsigned int", "Uint32": "unsigned long", "Uint64": "unsigned long long",
    "int16": "int", "int32": "long", "int64": "long long", "Int16": "int", "Int32": "long",
    "Int64": "long long", "Int8": "char", "Uint8": "unsigned char", "Int": "int", "Uns": "unsigned int",
    "Char": "char", "Bool": "unsigned int", "float32": "float", "float64": "long double",
    "Float32": "float", "int16_t": "int", "uint16_t": "unsigned int", "int32_t": "long",
    "uint32_t": "unsigned long", "int64_t": "long long", "uint64_t": "unsigned long long",
    "int8_t": "char", "uint8_t": "unsigned char", "String": "char *", "Ptr": "void *",
}
"""Type names a lab uses without declaring them (from the framework's headers or ``<stdint.h>``)."""

HOST_TYPES = {
    # how crslab's host build of the same headers declares them (csrc/firmware/include)
    "Uint16": "uint16_t", "Uint32": "uint32_t", "Uint64": "uint64_t", "int16": "int16_t",
    "int32": "int32_t", "int64": "int64_t", "Int16": "int16_t", "Int32": "int32_t", "Int64": "int64_t",
    "Int8": "int8_t", "Uint8": "uint8_t", "Int": "int", "Uns": "unsigned int", "Char": "char",
    "Bool": "unsigned short", "float32": "float", "float64": "long double", "Float32": "float",
    "String": "char *", "Ptr": "void *", "bool": "_Bool",
}
"""The host C type each framework type name is compiled as (for cffi declarations)."""

WASM32_TYPES = {
    "char": "int8_t", "signed char": "int8_t", "unsigned char": "uint8_t", "short": "int16_t",
    "unsigned short": "uint16_t", "int": "int16_t", "unsigned int": "uint16_t", "long": "int32_t",
    "unsigned long": "uint32_t", "long long": "int64_t", "unsigned long long": "uint64_t",
    "float": "float", "double": "float", "long double": "float", "_Bool": "uint8_t", "bool": "uint8_t",
    "int8_t": "int8_t", "uint8_t": "uint8_t", "int16_t": "int16_t", "uint16_t": "uint16_t",
    "int32_t": "int32_t", "uint32_t": "uint32_t", "int64_t": "int64_t", "uint64_t": "uint64_t",
}
"""A C type (qualifiers dropped) to the fixed-width type it has in a WebAssembly firmware, whose lab
is compiled with the C28x's widths (crslab/lab/c28x_ir.py): ``int`` 16 bits, ``long`` 32, ``double``
and ``long double`` a 32-bit float, ``char`` 8 bits (16 on the C28x); pointers have none crslab
reads."""


def wasm_element_type(ctype: str, pointer: bool = False) -> str | None:
    """The cffi type of one element of a variable of ``ctype`` in a WebAssembly firmware.

    >>> [wasm_element_type(t) for t in ("int", "long", "Uint16", "double")]
    ['int16_t', 'int32_t', 'uint16_t', 'float']
    """
    if pointer:
        return None
    host = HOST_TYPES.get(ctype, ctype)
    return WASM32_TYPES.get(host)


@dataclass(frozen=True)
class LabVariable:
    """One global variable of a lab file.

    ``ctype`` is its type as written, qualifiers dropped and spaces normalised (``float``,
    ``unsigned long``, ``Uint16``, or a typedef of the lab's own resolved to one of those);
    ``dims`` its array dimensions (``()`` for a scalar); ``section`` the ``DATA_SECTION`` it is
    placed in (None: the compiler's own, ``.ebss``); ``line`` where it is declared (1-based), in
    ``file``: empty for the lab file itself, else the name of its own header it is in
    (:func:`crslab.lab.includes.own_variables`).
    """

    name: str
    ctype: str
    dims: tuple[int, ...]
    pointer: bool
    static: bool
    const: bool
    section: str | None
    initial: str | None
    line: int
    file: str = ""

    @property
    def length(self) -> int | None:
        """Elements of an array (all dimensions), None for a scalar."""
        return math.prod(self.dims) if self.dims else None

    @property
    def host_ctype(self) -> str:
        """The type as the host compiles it (a cffi declaration's type)."""
        return "void *" if self.pointer else HOST_TYPES.get(self.ctype, self.ctype)


def array_length(expr: str, defines: dict[str, str]) -> int | None:
    """An array size such as ``100``, ``N`` or ``3 * MAX_POINTS`` (integer #defines only).

    >>> array_length("3 * MAX_WP", {"MAX_WP": "20"})
    60
    >>> array_length("sizeof(x)", {}) is None
    True
    """
    text = re.sub(r"[A-Za-z_]\w*", lambda m: defines.get(m.group(0), "?"), expr)
    if not _SIZE_EXPR.match(text):
        return None
    try:
        value = eval(text, {"__builtins__": {}})  # noqa: S307 - digits and + - * ( ) only
    except (SyntaxError, ZeroDivisionError):
        return None
    return int(value) if isinstance(value, int) and value > 0 else None


def strip_comments(text: str, literals: bool = False) -> str:
    """Comments blanked (newlines kept, so line numbers stay); with ``literals`` string and
    character literals emptied too (so their braces and semicolons are not code).

    >>> strip_comments('x = "a;b"; // c', literals=True)
    'x = "   "; '
    """

    def blank(m: re.Match[str]) -> str:
        s = m.group(0)
        if s.startswith("/*"):
            return re.sub(r"[^\n]", " ", s)
        if s.startswith("//"):
            return ""
        return s[0] + " " * (len(s) - 2) + s[-1] if literals else s

    return re.sub(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', blank, text,
                  flags=re.DOTALL)


def _without_preprocessor(text: str) -> str:
    """Preprocessor lines (and their continuations) blanked; the lines of an ``#if 0`` block too
    (up to its ``#else``, ``#elif`` or ``#endif``)."""
    out: list[str] = []
    skipping = 0  # nesting depth inside an #if 0 block; 0: the lines are live
    continued = False
    for line in text.split("\n"):
        directive = re.match(r"\s*#\s*(\w*)(.*)", line)
        if directive and not continued:
            word, arg = directive.group(1), directive.group(2).strip()
            if skipping:
                if word in ("if", "ifdef", "ifndef"):
                    skipping += 1
                elif word == "endif" or (word in ("else", "elif") and skipping == 1):
                    skipping -= 1 if word == "endif" else skipping
            elif word == "if" and arg == "0":
                skipping = 1
        if directive or continued:
            continued = line.rstrip().endswith("\\")
            out.append("")
            continue
        out.append("" if skipping else line)
    return "\n".join(out)


def _split_top(text: str, sep: str) -> list[str]:
    """``text`` split at ``sep`` outside parentheses, brackets and braces."""
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == sep and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return parts


def _matching_brace(code: str, i: int) -> int:
    """The index of the ``}`` closing the ``{`` at ``i`` (the end of ``code`` if none)."""
    depth = 0
    for j in range(i, len(code)):
        if code[j] == "{":
            depth += 1
        elif code[j] == "}":
            depth -= 1
            if depth == 0:
                return j
    return len(code)


def _statements(code: str) -> list[tuple[str, int]]:
    """Every declaration at file scope, with the offset it starts at. Function bodies are skipped;
    so are ``struct``/``union``/``enum`` types and anything declared with one; an initialiser list
    stays in its declaration."""
    out: list[tuple[str, int]] = []
    start, i = 0, 0
    while i < len(code):
        ch = code[i]
        if ch == "{":
            head = code[start:i]
            close = _matching_brace(code, i)
            if "=" in head:  # an initialiser list: part of the declaration
                i = close + 1
                continue
            if re.search(r"\b(struct|union|enum)\b", head):  # a type (and its variables): skipped
                end = code.find(";", close)
                i = start = (end if end >= 0 else len(code)) + 1
                continue
            i = start = close + 1  # a function's body
            continue
        if ch == ";":
            out.append((code[start:i], start))
            start = i + 1
        i += 1
    return out


_DECLARATOR = re.compile(r"^(?P<stars>[\s*]*)(?P<name>[A-Za-z_]\w*)\s*(?P<dims>(?:\[[^\]]*\]\s*)*)"
                         r"(?:=\s*(?P<init>.*))?$", re.DOTALL)


def _base_type(words: list[str], typedefs: dict[str, tuple[str, bool]]) -> tuple[str, bool] | None:
    """The type of a declaration's specifier words (qualifiers dropped): ``(ctype, is_pointer)``."""
    kept = [w for w in words if w not in _QUALIFIERS]
    if len(kept) == 1 and (kept[0] in FRAMEWORK_TYPES or kept[0] in typedefs):
        if kept[0] in typedefs:
            return typedefs[kept[0]]
        return (kept[0], False) if not FRAMEWORK_TYPES[kept[0]].endswith("*") else (kept[0], True)
    if not kept or any(w not in _KEYWORDS for w in kept):
        return None
    if kept == ["void"]:
        return ("void", False)
    signed = "unsigned" if "unsigned" in kept else ("signed" if "signed" in kept and "char" in kept else "")
    longs = kept.count("long")
    if "float" in kept:
        base = "float"
    elif "double" in kept:
        base = "long double" if longs else "double"
    elif "char" in kept:
        base = "char"
    elif "_Bool" in kept or "bool" in kept:
        base = "_Bool" if "_Bool" in kept else "bool"
    elif "short" in kept:
        base = "short"
    elif longs >= 2:
        base = "long long"
    elif longs == 1:
        base = "long"
    else:
        base = "int"
    return (f"{signed} {base}".strip(), False)


def _initial_count(init: str) -> int | None:
    """Elements of a one-dimensional initialiser list ``{a, b, c}``."""
    init = init.strip()
    if not (init.startswith("{") and init.endswith("}")):
        return None
    items = [p for p in _split_top(init[1:-1], ",") if p.strip()]
    return len(items) or None


def find_variables(source_text: str) -> list[LabVariable]:
    """Every variable defined at file scope in ``source_text``, in file order (see the module)."""
    text = strip_comments(source_text)
    sections = {name: section for name, section in _PRAGMA.findall(text)}
    defines = dict(_DEFINE.findall(text))
    code = _without_preprocessor(strip_comments(source_text, literals=True))
    typedefs: dict[str, tuple[str, bool]] = {}
    out: list[LabVariable] = []
    for statement, offset in _statements(code):
        if re.search(r"\b(struct|union|enum)\b", statement):
            continue
        words, rest, typed = [], "", False
        for token in re.finditer(r"[A-Za-z_]\w*|\S", statement):
            w = token.group(0)
            named_type = w in FRAMEWORK_TYPES or w in typedefs
            if w in _QUALIFIERS or w in _KEYWORDS or (named_type and not typed):
                words.append(w)
                typed = typed or (w not in _QUALIFIERS and w not in ("signed", "unsigned"))
                continue
            rest = statement[token.start():]
            break
        base = _base_type(words, typedefs)
        if base is None:
            continue
        line = code.count("\n", 0, offset + len(statement) - len(statement.lstrip())) + 1
        for declarator in _split_top(rest, ","):
            pre = _split_top(declarator, "=")[0]
            if "(" in pre:  # a function, or a pointer to one
                break
            m = _DECLARATOR.match(declarator.strip())
            if m is None:
                continue
            pointer = base[1] or "*" in m.group("stars")
            if "typedef" in words:
                typedefs[m.group("name")] = (base[0], pointer)
                continue
            if "extern" in words or (base[0] == "void" and not pointer):
                continue
            dims: list[int] = []
            init = m.group("init").strip() if m.group("init") else None
            for size in re.findall(r"\[([^\]]*)\]", m.group("dims")):
                n = array_length(size, defines) if size.strip() else (
                    _initial_count(init) if init is not None and len(dims) == 0 else None)
                if n is None:
                    break
                dims.append(n)
            else:
                found = LabVariable(m.group("name"), base[0], tuple(dims), pointer, "static" in words,
                                    "const" in words, sections.get(m.group("name")),
                                    " ".join(init.split()) if init else None, line)
                before = next((i for i, v in enumerate(out) if v.name == found.name), None)
                if before is None:
                    out.append(found)
                elif init and out[before].initial is None:  # a tentative definition, then one with a value
                    out[before] = found
    return out


def variables_of_files(files: Sequence[tuple[str, str]]) -> list[LabVariable]:
    """:func:`find_variables` of several files (name, text) read as one, in order, as the compiler
    reads a lab and the headers it includes (a header's ``typedef``, ``#define`` or ``DATA_SECTION``
    counts for the lab's variables, a tentative definition and one with a value are one variable),
    each variable with the name of the file it is in and its line there.

    >>> vs = variables_of_files([("gains.h", '#pragma DATA_SECTION(Kp, ".my_vars")\\nfloat Kp;\\n'),
    ...                          ("", "int mode;\\nfloat Kp = 2.5;\\n")])
    >>> [(v.name, v.file, v.line, v.section, v.initial) for v in vs]
    [('Kp', '', 2, '.my_vars', '2.5'), ('mode', '', 1, None, None)]
    """
    texts, starts, line = [], [], 1
    for name, text in files:
        text = text if text.endswith("\n") else text + "\n"
        starts.append((line, name))
        texts.append(text)
        line += text.count("\n")
    out = []
    for v in find_variables("".join(texts)):
        first, name = max(s for s in starts if s[0] <= v.line)
        out.append(dataclasses.replace(v, file=name, line=v.line - first + 1))
    return out

