"""A lab compiled with the C28x's widths, moved to WebAssembly: the LLVM IR of clang's AVR front end,
rewritten for wasm32.

clang has no wasm32 target whose ``int`` is 16 bits, and no option that makes one. Its AVR front end
has the C28x's widths (``int`` and ``short`` 16 bits, ``long`` 32, ``long long`` 64, ``float`` and
``double`` 32: the F28335's COFF ABI), so crslab compiles the lab with it, optimisation off, to LLVM
IR, whose types and operations say those widths exactly (``add i16`` wraps at 16 bits, ``fadd
float`` rounds to a float, in any back end), and :func:`to_wasm32` moves that IR to wasm32, where
zig's clang compiles it as any other (:mod:`crslab.lab.firmware`):

- the target's lines (data layout, triple), AVR's program address space and CPU attributes;
- every struct type and constant packed: AVR aligns nothing, so the sizes the front end already
  computed (``sizeof``, a struct's copy) hold in the wasm32 layout too (:func:`pack_structs`);
- each argument an outside variadic function receives (``serial_printf``, ``printf``...) widened as
  C promotes it on wasm32: an ``int`` to 32 bits, a ``double`` (a float here) to 64, so the
  framework and the C library read what they are given (:func:`widen_variadic_calls`);
- a pointer made from an integer (16 bits wide here) that is not NULL points far past the
  firmware's memory, so a store through it stops the run at its line (:func:`wild_pointers`);
- an integer division by zero (or of the most negative integer by -1), which WebAssembly traps on,
  and a float converted to 16 bits give what the C28x's give (:mod:`crslab.lab.c28x_arithmetic`);
- the lab's globals placed as the TI linker places them (:func:`place_globals`): one block stands
  for the F28335's data memory, each variable an alias into it at twice its word offset, so a store
  past an array's end meets the neighbour it meets on the board.

What the AVR front end cannot give the lab (docs/framework.md section 9): a ``char`` of 16 bits (8
here), a 64-bit ``long double`` (32 here), and pointers of the C28x's size: a pointer is 4 bytes in
memory here but ``sizeof`` says 2, so a lab that allocates or copies pointers by ``sizeof`` gets half.

>>> ir = '''target datalayout = "e-P1-p:16:8-i8:8-i16:8-i32:8-i64:8-f32:8-f64:8-n8:16-a:8"
... target triple = "avr-unknown-unknown-unknown"
... %struct.S = type { i16, float }
... @count = dso_local global i16 0, align 1, !dbg !0
... declare dso_local i16 @serial_printf(ptr noundef, ptr noundef, ...) addrspace(1) #1
... define dso_local void @lab() addrspace(1) #0 {
...   %1 = load i16, ptr @count, align 1
...   %2 = call addrspace(1) i16 (ptr, ptr, ...) @serial_printf(ptr null, ptr null, i16 noundef %1)
...   ret void
... }'''
>>> out, placed = to_wasm32(ir, Placement((("count", 2),), 8))
>>> print("\\n".join(line for line in out.splitlines() if "struct" in line or "crs" in line))
%struct.S = type <{ i16, float }>
@crs.c28x.ram = hidden global <{ [2 x i8], i16, [4 x i8] }> <{ [2 x i8] zeroinitializer, i16 0, [4 x i8] \
zeroinitializer }>, align 4
@count = dso_local alias i16, getelementptr (i8, ptr @crs.c28x.ram, i32 2)
  %crs.va1 = sext i16 %1 to i32
  %2 = call i16 (ptr, ptr, ...) @serial_printf(ptr null, ptr null, i32 noundef %crs.va1)
>>> placed
['count']
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from crslab.lab.c28x_arithmetic import c28x_arithmetic
from crslab.lab.c28x_memory import MemoryLayout

WASM32_DATALAYOUT = "e-m:e-p:32:32-p10:8:8-p20:8:8-i64:64-i128:128-n32:64-S128-ni:1:10:20"
WASM32_TRIPLE = "wasm32-unknown-wasip1-unknown"
"""What zig's clang writes for ``--target=wasm32-wasi`` (the IR must say exactly this)."""
RAM_SYMBOL = "crs.c28x.ram"
"""The block that stands for the F28335's data memory (a dot: no C name, so none of the lab's, is it)."""
WILD_BASE = 0x80000000
"""Where a pointer made from a non-zero integer points: past any firmware's memory (a store traps)."""

_STRING = re.compile(r'"[^"]*"')  # IR escapes a quote inside a string as \22
_NAME = r'@(?:[-\w.$]+|"[^"]*")'
_DEFINE = re.compile(rf"^define\b[^@]*({_NAME})\(")
_GLOBAL = re.compile(rf"^({_NAME}) = ((?:[\w()]+ )*?)(global|constant) (.*)$")
_TYPE_DEF = re.compile(r'^(%[-\w.$]+|%"[^"]*") = type (.*)$')


class IRError(ValueError):
    """IR this module cannot move (a construct it does not know): crslab's own limit, said as such."""


def _string_mask(line: str) -> list[bool]:
    mask = [False] * len(line)
    for m in _STRING.finditer(line):
        mask[m.start():m.end()] = [True] * (m.end() - m.start())
    return mask


def _map_code(line: str, change: Callable[[str], str]) -> str:
    """``line`` with ``change`` applied to each part outside string constants and quoted names."""
    out, at = [], 0
    for m in _STRING.finditer(line):
        out += [change(line[at:m.start()]), m.group(0)]
        at = m.end()
    return "".join([*out, change(line[at:])])


def _closing(text: str, i: int, mask: list[bool] | None = None) -> int:
    """The index of the bracket closing the one at ``i`` (any of ``([{<``)."""
    mask = mask if mask is not None else _string_mask(text)
    depth = 0
    for j in range(i, len(text)):
        if mask[j]:
            continue
        if text[j] in "([{<":
            depth += 1
        elif text[j] in ")]}>":
            depth -= 1
            if depth == 0:
                return j
    raise IRError(f"unbalanced brackets in {text[:60]!r}")


def _split_top(text: str) -> list[str]:
    """``text`` split at its commas outside brackets and strings."""
    mask = _string_mask(text)
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if mask[i]:
            continue
        if ch in "([{<":
            depth += 1
        elif ch in ")]}>":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    return [*parts, text[start:]]


def _pack_line(line: str, keep_last: bool) -> str:
    """Every struct brace of ``line`` packed (``{`` to ``<{``, its ``}`` to ``}>``); with
    ``keep_last`` the last ``{``, a function body's, is kept."""
    mask = _string_mask(line)
    opens = [i for i, ch in enumerate(line) if ch == "{" and not mask[i]]
    if keep_last and opens:
        opens = opens[:-1]
    swap: dict[int, str] = {}
    for i in opens:
        if i > 0 and line[i - 1] in "!<":  # metadata, or packed already
            continue
        depth = 0
        for j in range(i, len(line)):
            if mask[j] or line[j] not in "{}":
                continue
            depth += 1 if line[j] == "{" else -1
            if depth == 0:
                swap[i], swap[j] = "<{", "}>"
                break
    return "".join(swap.get(i, ch) for i, ch in enumerate(line)) if swap else line


def pack_structs(lines: list[str]) -> list[str]:
    """Every struct type and constant packed, as AVR lays them out: AVR aligns nothing, so a struct
    has no padding there; packed, it has none in wasm32 either and every size the front end
    computed holds. Intrinsics' and atomics' own result types are left as they are.

    >>> ir = ["%struct.S = type { i16, float }", "@s = global %struct.S { i16 1, float 2.0 }",
    ...       "define void @f() {", "}"]
    >>> print("\\n".join(pack_structs(ir)))
    %struct.S = type <{ i16, float }>
    @s = global %struct.S <{ i16 1, float 2.0 }>
    define void @f() {
    }
    """
    out = []
    for line in lines:
        s = line.lstrip()
        if (not s or s[0] in "!;}#" or s.startswith(("attributes ", "source_filename", "target "))
                or "@llvm." in line or " cmpxchg " in line or " atomicrmw " in line):
            out.append(line)
        else:
            out.append(_pack_line(line, keep_last=s.startswith("define ")))
    return out


_VARIADIC_CALL = re.compile(rf"\bcall\b[^@]*?\(([^()]*)\.\.\.\) ({_NAME})\(")
_NARROW = re.compile(r"^(i8|i16|float)((?:\s+(?:noundef|signext|zeroext))*)\s+(.+)$")
_LITERAL = re.compile(r"-?\d+|0x[0-9A-Fa-f]+|[-+]?\d+\.\d*(?:e[-+]?\d+)?")


def widen_variadic_calls(lines: list[str], defined: set[str], counter: list[int]) -> list[str]:
    """Each call of a variadic function the lab does not define (``defined``: the IR's own) passes
    its variadic ``i16``/``i8`` arguments sign-extended to ``i32`` and its ``float`` ones as
    ``double``, as a wasm32 caller does: the callee's ``va_arg(ap, int)`` and ``va_arg(ap,
    double)`` read them. A variadic function of the lab's own keeps the lab's widths. ``counter``
    numbers the new values.

    >>> call = "  %3 = call i16 (ptr, ...) @printf(ptr @.s, i16 %2, float 1.5)"
    >>> print("\\n".join(widen_variadic_calls([call], set(), [0])))
      %crs.va1 = sext i16 %2 to i32
      %3 = call i16 (ptr, ...) @printf(ptr @.s, i32 %crs.va1, double 1.5)
    """
    out = []
    for line in lines:
        m = _VARIADIC_CALL.search(line) if "..." in line else None
        if m is None or m.group(2) in defined:
            out.append(line)
            continue
        fixed = len([p for p in _split_top(m.group(1)) if p.strip()])
        open_ = m.end() - 1
        close = _closing(line, open_)
        indent = line[:len(line) - len(line.lstrip())]
        before, args = [], []
        for k, arg in enumerate(_split_top(line[open_ + 1:close])):
            a = arg.strip()
            narrow = _NARROW.match(a) if k >= fixed else None
            if narrow is None:
                args.append(a)
                continue
            ty, attrs, value = narrow.groups()
            wide = "double" if ty == "float" else "i32"
            if _LITERAL.fullmatch(value):  # a constant is the same number in the wider type
                args.append(f"{wide}{attrs} {value}")
                continue
            counter[0] += 1
            name = f"%crs.va{counter[0]}"
            before.append(f"{indent}{name} = {'fpext' if ty == 'float' else 'sext'} {ty} {value} to {wide}")
            args.append(f"{wide}{attrs} {name}")
        out += [*before, line[:open_ + 1] + ", ".join(args) + line[close:]]
    return out


_INTTOPTR = re.compile(r"^(\s*)(%[-\w.]+) = inttoptr (i8|i16) (\S+) to ptr(.*)$")
_INTTOPTR_CONSTANT = re.compile(r"inttoptr \((i8|i16) (-?\d+) to ptr\)")


def wild_address(value: int, bits: int) -> int:
    """Where a pointer made from the ``bits``-wide integer ``value`` points in the firmware.

    >>> wild_address(0, 16), hex(wild_address(-16, 16))
    (0, '0x8000fff0')
    """
    v = value & ((1 << bits) - 1)
    return 0 if v == 0 else WILD_BASE | v


def _wild_constant(m: re.Match[str]) -> str:
    return f"inttoptr (i32 {wild_address(int(m.group(2)), int(m.group(1)[1:]))} to ptr)"


def wild_pointers(lines: list[str], counter: list[int]) -> list[str]:
    """Each pointer made from an integer (16 bits on the C28x's widths) points past the firmware's
    memory unless it is NULL (:func:`wild_address`): on the board such a pointer reaches whatever
    that address holds, in the firmware it would land in the firmware's own stack; here a store or
    a load through it stops the run at its line, as a wild pointer does in crslab."""
    out = []
    for line in lines:
        if "inttoptr" not in line:
            out.append(line)
            continue
        m = _INTTOPTR.match(line)
        if m is None:
            out.append(_map_code(line, lambda code: _INTTOPTR_CONSTANT.sub(_wild_constant, code)))
            continue
        indent, name, ty, value, rest = m.groups()
        counter[0] += 1
        t = f"%crs.wild{counter[0]}"
        out += [f"{indent}{t}.z = zext {ty} {value} to i32", f"{indent}{t}.nz = icmp ne {ty} {value}, 0",
                f"{indent}{t}.w = or i32 {t}.z, {WILD_BASE}",
                f"{indent}{t}.s = select i1 {t}.nz, i32 {t}.w, i32 0",
                f"{indent}{name} = inttoptr i32 {t}.s to ptr{rest}"]
    return out


_SIZES = {"float": 4, "double": 8, "half": 2, "ptr": 4}


def type_size(ty: str, named: dict[str, str]) -> int:
    """Bytes of the (packed) IR type ``ty``; ``named`` holds the module's named types.

    >>> type_size("[3 x <{ i16, float }>]", {}), type_size("%s", {"%s": "<{ ptr, i1 }>"})
    (18, 5)
    """
    ty = ty.strip()
    if re.fullmatch(r"i\d+", ty):
        return (int(ty[1:]) + 7) // 8
    if ty in _SIZES:
        return _SIZES[ty]
    array = re.fullmatch(r"\[\s*(\d+)\s+x\s+(.+)\]", ty, re.DOTALL)
    if array is not None:
        return int(array.group(1)) * type_size(array.group(2), named)
    if ty.startswith("<{") and ty.endswith("}>"):
        inner = ty[2:-2].strip()
        return sum(type_size(p, named) for p in _split_top(inner)) if inner else 0
    if ty in named:
        return type_size(named[ty], named)
    raise IRError(f"the IR type {ty[:40]} has no size crslab knows")


def _take_type(text: str) -> tuple[str, str]:
    """The IR type at the start of ``text``, and the rest."""
    text = text.lstrip()
    if text[:1] in "[{<":
        end = _closing(text, 0)
        return text[:end + 1], text[end + 1:]
    m = re.match(r'%[-\w.$]+|%"[^"]*"|\w+', text)
    if m is None:
        raise IRError(f"no IR type at {text[:40]!r}")
    return m.group(0), text[m.end():]


@dataclass(frozen=True)
class Placement:
    """Where the lab's globals go in the block (:data:`RAM_SYMBOL`) and how big it is (bytes)."""

    offsets: tuple[tuple[str, int], ...]
    """(name in the IR, byte offset) of each global with a place."""
    size: int
    framework: tuple[tuple[str, str, int], ...] = ()
    """The framework's variables the block defines where the lab does not: (name, IR type, offset)."""


FRAMEWORK_IR_TYPES = {"matlabLock": "float", **{f"SIMU_Var{i}_fromSIMU_16bit": "i16" for i in range(1, 8)}}
"""The framework's variables of the map (:mod:`crslab.lab.c28x_memory`), as the block defines them
where the lab does not: Simulink's inputs are ints, Gen A's matlabLock a float."""
RENAMED_PREFIX = "crs_lab_"
"""The prefix of a lab global the build renamed (crslab.lab.firmware.RENAMED_PREFIX)."""


def placement(memory: MemoryLayout, renamed: Sequence[str] = ()) -> Placement:
    """Where each variable of ``memory`` (the TI linker's layout of the lab's globals) goes in the
    block: twice its word offset from the first section's origin (a word is two bytes, an ``int``
    one word and a ``float`` two on both), the block as long as the sections it spans, gaps
    included. ``renamed``: the lab's globals compiled under :data:`RENAMED_PREFIX`.

    >>> from crslab.generations import GEN_A
    >>> from crslab.lab.c28x_memory import layout
    >>> from crslab.lab.variables import find_variables
    >>> mem = layout(find_variables("int mode; float gain;"), GEN_A, "lab")
    >>> p = placement(mem)
    >>> p.offsets[:2], p.framework[0]
    ((('mode', 0), ('gain', 4)), ('SIMU_Var1_fromSIMU_16bit', 'i16', 8))
    """
    if not memory.variables:
        return Placement((), 0)
    base = min(s.origin for s in memory.sections)
    end = max(v.address + v.words for v in memory.variables)
    offsets = tuple((RENAMED_PREFIX + v.name if v.name in renamed else v.name, 2 * (v.address - base))
                    for v in memory.variables)
    framework = tuple((v.name, FRAMEWORK_IR_TYPES[v.name], 2 * (v.address - base))
                      for v in memory.variables if v.name in FRAMEWORK_IR_TYPES)
    return Placement(offsets, 2 * (end - base), framework)


@dataclass(frozen=True)
class _Global:
    index: int
    linkage: str
    type: str
    init: str


def _declarations(lines: list[str], wanted: set[str]) -> dict[str, int]:
    """The lines declaring (``external``) the globals ``wanted``: name -> line index."""
    found = {}
    for i, line in enumerate(lines):
        m = _GLOBAL.match(line)
        if m is not None and m.group(1)[1:] in wanted and "external" in m.group(2).split():
            found[m.group(1)[1:]] = i
    return found


def _definitions(lines: list[str], wanted: set[str]) -> dict[str, _Global]:
    found = {}
    for i, line in enumerate(lines):
        m = _GLOBAL.match(line)
        if m is None or m.group(1)[1:] not in wanted or "external" in m.group(2).split():
            continue
        ty, after = _take_type(m.group(4))
        linkage = "internal" if "internal" in m.group(2).split() else "dso_local"
        found[m.group(1)[1:]] = _Global(i, linkage, ty, _split_top(after)[0].strip())
    return found


def place_globals(lines: list[str], placement: Placement) -> tuple[list[str], list[str]]:
    """The globals of ``placement`` moved into one block at their offsets, each an alias of its own
    name (so its symbol, its export and every use stay); a global whose type does not fit before
    its neighbour keeps the place the compiler gave it. Returns the lines and the names placed."""
    named = {m.group(1): m.group(2) for line in lines if (m := _TYPE_DEF.match(line))}
    wanted = dict(placement.offsets)
    found = _definitions(lines, set(wanted))
    members = [(wanted[n], n, g.type, g.init, g.linkage) for n, g in found.items()]
    members += [(offset, n, ty, "zeroinitializer", "dso_local") for n, ty, offset in placement.framework
                if n not in found]
    types, inits, aliases, placed = [], [], [], []
    at = 0
    for offset, name, ty, init, linkage in sorted(members):
        size = type_size(ty, named)
        if offset < at or offset + size > placement.size:
            continue
        if offset > at:
            types.append(f"[{offset - at} x i8]")
            inits.append(f"[{offset - at} x i8] zeroinitializer")
        types.append(ty)
        inits.append(f"{ty} {init}")
        aliases.append(f"@{name} = {linkage} alias {ty}, getelementptr (i8, ptr @{RAM_SYMBOL}, i32 {offset})")
        placed.append(name)
        at = offset + size
    if placement.size > at:
        types.append(f"[{placement.size - at} x i8]")
        inits.append(f"[{placement.size - at} x i8] zeroinitializer")
    # the lab's own definitions move into the block; its declarations of the framework's variables
    # (``extern int SIMU_Var1_fromSIMU_16bit;``) give way to the block's definitions
    declared = _declarations(lines, {n for n, _, _ in placement.framework})
    moved = {found[n].index for n in placed if n in found} | {declared[n] for n in placed if n in declared}
    kept = [line for i, line in enumerate(lines) if i not in moved]
    block = [f"@{RAM_SYMBOL} = hidden global <{{ {', '.join(types)} }}> <{{ {', '.join(inits)} }}>, align 4",
             *aliases]
    tops = ("@", "define ", "declare ")
    first = next((k for k, line in enumerate(kept) if line.startswith(tops)), len(kept))
    return kept[:first] + block + kept[first:], placed


def to_wasm32(text: str, placement: Placement | None = None) -> tuple[str, list[str]]:
    """The AVR IR ``text`` moved to wasm32 (see the module); with ``placement`` its globals placed.
    Returns the IR and the names placed."""
    lines = text.split("\n")
    defined = {m.group(1) for line in lines if (m := _DEFINE.match(line))}
    moved = []
    for line in lines:
        if line.startswith("target datalayout"):
            line = f'target datalayout = "{WASM32_DATALAYOUT}"'
        elif line.startswith("target triple"):
            line = f'target triple = "{WASM32_TRIPLE}"'
        elif line.startswith("attributes #"):
            line = re.sub(r'\s*"target-(?:cpu|features)"="[^"]*"', "", line)
        elif "addrspace(1)" in line:
            line = _map_code(line, lambda code: code.replace(" addrspace(1)", ""))
        moved.append(line)
    counter = [0]
    lines = wild_pointers(widen_variadic_calls(pack_structs(moved), defined, counter), counter)
    lines = c28x_arithmetic(lines)
    if placement is None:
        return "\n".join(lines), []
    lines, placed = place_globals(lines, placement)
    return "\n".join(lines), placed
