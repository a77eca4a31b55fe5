"""Integer arithmetic where WebAssembly and the C28x part ways: a division by zero and a float
converted to a 16-bit integer.

**Divisions.** WebAssembly traps on an integer division by zero and on the most negative integer
divided by -1; the C28x traps on neither. Its divisions (``int``, ``long``, ``long long``, signed
or not) run the conditional subtraction ``SUBCU``/``SUBCUL`` once per bit, on the operands'
magnitudes, and the signed ones negate the quotient when the operands' signs differ (TI, *TMS320C28x CPU and
Instruction Set Reference Guide*, SPRU430, "SUBCU": ``temp = ACC << 1 - den << 16``; if no
borrow, ``ACC = temp + 1``, else ``ACC = ACC << 1``; the quotient ends in the low half, the
remainder in the high half). With a zero divisor no subtraction ever borrows, so:

- unsigned: the quotient is all ones (65535 for an ``unsigned int``), the remainder the dividend;
- signed: the quotient is -1 (all ones) for a dividend >= 0, negated to 1 for a negative one; the
  remainder is the dividend;
- the most negative integer divided by -1 is itself (its magnitude, negated, wraps), remainder 0.

Every ``sdiv``, ``udiv``, ``srem`` and ``urem`` of the lab's IR (with the C28x's widths,
:mod:`crslab.lab.c28x_ir`) whose divisor is not a constant that needs none of this becomes a call
of a small function that gives these results and divides as before otherwise. So a lab that divides
by zero goes on as on the board (``crslab sim --sanitize`` stops at the line instead,
docs/debugging.md).

**A float to a 16-bit integer.** The C28x's FPU converts with ``F32TOI16`` and ``F32TOUI16``, which
saturate at the 16-bit range (TI, *TMS320C28x Floating Point Unit and Instruction Set Reference
Guide*, SPRUEO2); WebAssembly has no 16-bit conversion, and clang's converts to 32 bits (saturating)
and keeps the low 16, so ``(int)1e20f`` would be -1 rather than 32767. Each ``fptosi``/``fptoui``
of a float to ``i16`` becomes LLVM's saturating conversion to 16 bits (NaN gives 0: crslab's model,
as for ``%f``'s NaN, docs/framework.md section 7). A ``long`` is converted with ``F32TOI32``, which
saturates as WebAssembly's does.

>>> ir = ["  %3 = sdiv i16 %1, %2, !dbg !7", "  %4 = udiv i16 %1, 8", "  %5 = fptosi float %0 to i16"]
>>> print("\\n".join(c28x_arithmetic(ir)[:3]))
  %3 = call i16 @crs.c28x.sdiv.i16(i16 %1, i16 %2), !dbg !7
  %4 = udiv i16 %1, 8
  %5 = call i16 @llvm.fptosi.sat.i16.f32(float %0)
"""

from __future__ import annotations

import re

_DIVISION = re.compile(r"^(\s*%[-\w.$]+ = )(sdiv|udiv|srem|urem)(?: exact)? (i8|i16|i32|i64) "
                       r"([^,]+), ([^,]+?)((?:, !.*)?)$")
_CONSTANT = re.compile(r"-?\d+")
_TO_SHORT = re.compile(r"^(\s*%[-\w.$]+ = )(fptosi|fptoui) float (\S+) to i16((?:, !.*)?)$")


def _needs_call(op: str, divisor: str) -> bool:
    """Whether a division by ``divisor`` (an IR operand) can differ from the C28x's in WebAssembly:
    any divisor but a literal other than 0 (and, signed, other than -1: clang's WebAssembly back
    end makes a division by a literal -1 a negation, which cannot trap, but nothing promises it)."""
    if not _CONSTANT.fullmatch(divisor):
        return True
    d = int(divisor)
    return d == 0 or (op[0] == "s" and d == -1)


def _helper(op: str, ty: str) -> str:
    """The IR of the function that does ``op`` on ``ty`` as the C28x does (see the module)."""
    name = f"@crs.c28x.{op}.{ty}"  # a dot: no C name, so no name of the lab's, is the same
    on_zero = {"sdiv": f"%n = icmp slt {ty} %a, 0\n  %q = select i1 %n, {ty} 1, {ty} -1\n  ret {ty} %q",
               "udiv": f"ret {ty} -1", "srem": f"ret {ty} %a", "urem": f"ret {ty} %a"}[op]
    body = [f"define internal {ty} {name}({ty} %a, {ty} %b) {{",
            f"  %z = icmp eq {ty} %b, 0", "  br i1 %z, label %zero, label %nonzero",
            "zero:", f"  {on_zero}", "nonzero:"]
    if op[0] == "s":  # the most negative by -1: the magnitude's quotient negated wraps; nothing remains
        body += [f"  %m = icmp eq {ty} %b, -1", "  br i1 %m, label %minus, label %divide", "minus:"]
        body += [f"  %r = sub {ty} 0, %a", f"  ret {ty} %r"] if op == "sdiv" else [f"  ret {ty} 0"]
        body += ["divide:"]
    body += [f"  %v = {op} {ty} %a, %b", f"  ret {ty} %v", "}"]
    return "\n".join(body)


def c28x_arithmetic(lines: list[str]) -> list[str]:
    """``lines`` (a module's IR) with each integer division that WebAssembly could trap on made a
    call of the C28x's division and each float converted to 16 bits saturating (see the module);
    the functions they call are defined or declared at the end."""
    out, used, converts = [], [], []
    for line in lines:
        c = _TO_SHORT.match(line) if " to i16" in line else None
        if c is not None:
            start, op, value, rest = c.groups()
            name = f"@llvm.{op}.sat.i16.f32"
            if name not in converts:
                converts.append(name)
            out.append(f"{start}call i16 {name}(float {value}){rest}")
            continue
        m = _DIVISION.match(line) if "div " in line or "rem " in line or "exact " in line else None
        if m is None or not _needs_call(m.group(2), m.group(5).strip()):
            out.append(line)
            continue
        start, op, ty, a, b, rest = m.groups()
        if (op, ty) not in used:
            used.append((op, ty))
        out.append(f"{start}call {ty} @crs.c28x.{op}.{ty}({ty} {a.strip()}, {ty} {b.strip()}){rest}")
    return [*out, *(_helper(op, ty) for op, ty in used), *(f"declare i16 {n}(float)" for n in converts)]
