"""One line of diagnosis for a WebAssembly firmware that stopped (``crs_board.trap``, sent by the
worker as a dict, see :func:`crslab.worker.main.trap_info`): what happened, in which function and
line of the lab file, where in the tick, and how the run is classed.

The board is trusted and the worker survives the firmware's trap, so the transcript up to the trap
is whole. wasmtime names the firmware's frames with their file and line (the firmware carries its
debug information); the first frame in the lab's own file is the line shown.

>>> t = {"kind": 3, "phase": 1, "tick": 5123, "exit_code": 0,
...      "text": "wasm backtrace:\\n    0:   0x1a - lab\\n      at /tmp/x/div.c:12:9\\n\\nCaused by: ..."}
>>> status, line = diagnose(t, "div.c", deadline_s=2.0)
>>> status
<RunStatus.CRASHED: 'crashed'>
>>> line.split(";")[0]
'div.c divided an integer by zero at div.c:12 in lab() at tick 5123 (t = 5.123 s)'
>>> diagnose({**t, "kind": 8, "text": ""}, "div.c", deadline_s=2.0)[1]
'div.c hung: lab() did not return within 2 s at tick 5123 (t = 5.123 s)'
>>> diagnose({**t, "kind": 8}, "div.c", deadline_s=2.0)[1].split("; ")[1]
'it was at div.c:12 in lab()'
"""

from __future__ import annotations

import re
from pathlib import Path, PurePath

from crslab._bindings import constants
from crslab.framework_facts import TICKS_PER_S
from crslab.run.status import RunStatus
from crslab.run.wasm_lines import line_at
from crslab.untrusted_text import for_terminal
from crslab.worker.share import board_ms

_AT = re.compile(r"^\s*at (.+?)(?::(\d+))?(?::\d+)?\s*$", re.MULTILINE)
_FRAME = re.compile(r"^\s*\d+:\s+0x[0-9a-f]+ - (\S+)", re.MULTILINE)
RECURSION_FRAMES = 8
"""A memory trap whose innermost frames are this many calls of one function ran off its stack."""


def recursed(text: str) -> bool:
    """Whether wasmtime's backtrace ``text`` starts with :data:`RECURSION_FRAMES` calls of one
    function (the stack ran off the bottom of the firmware's memory).

    >>> recursed("".join(f"  {i}: 0x10 - deep\\n" for i in range(9)))
    True
    """
    names = _FRAME.findall(text)[:RECURSION_FRAMES]
    return len(names) == RECURSION_FRAMES and len(set(names)) == 1


def where_in(text: str, lab_name: str) -> str | None:
    """``file:line`` of the innermost frame of wasmtime's backtrace ``text`` in the lab's own file.

    >>> where_in("  0: 0x1 - f\\n      at /a/b/lab.c:7:3\\n  1: 0x2 - g\\n      at /a/b/lab.c:20:1", "lab.c")
    'lab.c:7'
    """
    for path, line in _AT.findall(text):
        if PurePath(path).name == lab_name and line:
            return f"{lab_name}:{line}"
    return None


_FRAME_AT = re.compile(r"^\s*\d+:\s+(0x[0-9a-f]+) - (\S+)\n\s*at (.+?)(?::(\d+))?(?::\d+)?\s*$", re.MULTILINE)


def where_stopped(text: str, lab_name: str, image: Path | None = None) -> str:
    """Where in the lab's own file a firmware that was stopped (an interrupt) was: ``FILE:LINE in
    FUNCTION()`` of the innermost frame in the lab's file (a line wasmtime does not give, as for a
    loop's head, read from the firmware ``image``'s own line table: :mod:`crslab.run.wasm_lines`),
    ``in FUNCTION() (FILE)`` when its line is not known, else empty.

    >>> where_stopped("    0:   0x561a - wait_ready\\n        at /x/hang.c\\n    1: 0x50b - lab\\n"
    ...               "        at /x/hang.c:30:5\\n", "hang.c")
    'in wait_ready() (hang.c)'
    """
    for offset, function, path, line in _FRAME_AT.findall(text):
        if PurePath(path).name == lab_name:
            name = for_terminal(function)
            if not line and image is not None:
                try:
                    found = line_at(image.read_bytes(), int(offset, 16), lab_name)
                except OSError:
                    found = None
                line = str(found) if found else ""
            return f"at {lab_name}:{line} in {name}()" if line else f"in {name}() ({lab_name})"
    return ""


def too_slow(kind: int, text: str, lab_name: str, func: str, at: str, stopped: str) -> str:
    """The line for a call a shared worker ended (``CRS_FW_TRAP_TOO_COSTLY``, ``_TOO_LONG``): the
    board's first line of ``text`` says the limit it passed (``15000000 instructions``, ``20 ms``).

    >>> line = too_slow(constants.CRS_FW_TRAP_TOO_COSTLY, "5000000 instructions\\n...", "slow.c",
    ...                 "lab()", "at tick 4100 (t = 4.100 s)", "at slow.c:12 in lab()")
    >>> line.split(": ", 1)[1].split("; ")[0]
    'lab() cost more than 5,000,000 instructions in one call at tick 4100 (t = 4.100 s)'
    >>> line.split("; ")[2].split(",")[0]
    'the F28335 would need more than 33.3 ms for that call'
    """
    limit = re.match(r"\s*(\d+)", text)
    number = int(limit.group(1)) if limit else 0
    was = f"; it was {stopped}" if stopped else ""
    if kind == constants.CRS_FW_TRAP_TOO_COSTLY:
        board = (f"; the F28335 would need more than {board_ms(number):g} ms for that call, and the board "
                 f"calls {func} every {1000 / TICKS_PER_S:g} ms")
        what = f"cost more than {number:,} instructions"
    else:
        board = ""
        what = f"used more than {number} ms of the server's CPU time"
    return (f"{lab_name} is too slow for a shared server: {func} {what} in one call {at}{was}{board} "
            "(crslab sim runs it on, slower than real time)")


def _phase_words(phase: int) -> tuple[str, str]:
    """(the function it was in, where in the tick) for a phase."""
    c = constants
    if phase == c.CRS_PHASE_PRINTING:
        return "printing()", "in printing()"
    if phase == c.CRS_PHASE_LOADING:
        return "a constructor", "in a constructor or static initializer"
    return "lab()", "in lab()"


def diagnose(trap: dict, lab_name: str, *, deadline_s: float | None,
             image: Path | None = None) -> tuple[RunStatus, str]:
    """How the run ends and the one line that says why (``image``: the firmware, whose line table
    says where a hung call was when wasmtime does not)."""
    c = constants
    kind, phase, tick = int(trap.get("kind", 0)), int(trap.get("phase", 0)), int(trap.get("tick", 0))
    text = str(trap.get("text", ""))
    func, where = _phase_words(phase)
    at = ("before the first tick" if phase == c.CRS_PHASE_LOADING
          else f"at tick {tick} (t = {tick / TICKS_PER_S:.3f} s)")
    line = f"{lab_name}:{int(trap['line'])}" if int(trap.get("line", 0)) > 0 else where_in(text, lab_name)
    place = f"at {line} {where}" if line else where
    if kind == c.CRS_FW_TRAP_INTERRUPT:
        within = f" within {deadline_s:g} s" if deadline_s is not None else ""
        stopped = where_stopped(text, lab_name, image)
        was = f"; it was {stopped}" if stopped and stopped != f"in {func} ({lab_name})" else ""
        return RunStatus.HUNG, f"{lab_name} hung: {func} did not return{within} {at}{was}"
    if kind == c.CRS_FW_TRAP_STOPPED:  # the page's Stop (or the page went) ended the call
        return RunStatus.INTERRUPTED, f"stopped at t = {tick / TICKS_PER_S:.3f} s"
    if kind in (c.CRS_FW_TRAP_TOO_COSTLY, c.CRS_FW_TRAP_TOO_LONG):
        return RunStatus.HUNG, too_slow(kind, text, lab_name, func, at, where_stopped(text, lab_name, image))
    if kind == c.CRS_FW_TRAP_EXIT:
        return RunStatus.EXITED, f"{lab_name} called exit({int(trap.get('exit_code', 0))}) {place} {at}"
    if kind == c.CRS_FW_TRAP_REFUSED:
        what = for_terminal(text.split("\n", 1)[0])  # it quotes what the lab named
        return RunStatus.FORBIDDEN, f"{lab_name} was stopped by the sandbox: it tried to {what} {place} {at}"
    if kind == c.CRS_FW_TRAP_LOAD:
        first = for_terminal(text.split("\n", 1)[0]) if text else "no reason given"
        return RunStatus.CRASHED, f"{lab_name} cannot be run: {first}"
    what = {
        c.CRS_FW_TRAP_MEMORY: "read or wrote outside its memory (a wild pointer or an index far out of an "
                              "array)",
        c.CRS_FW_TRAP_STACK: "overflowed its call stack (runaway recursion)",
        c.CRS_FW_TRAP_DIVIDE: "divided an integer by zero",  # the C28x goes on: see the end of the line
        c.CRS_FW_TRAP_OVERFLOW: "overflowed an integer division (the most negative int divided by -1)",
        c.CRS_FW_TRAP_CONVERSION: "converted a float that is NaN or out of range to an integer",
        c.CRS_FW_TRAP_UNREACHABLE: "called abort() (or an assertion failed)",
        c.CRS_FW_TRAP_CALL: "called a function through a bad pointer",
        c.CRS_FW_TRAP_NULL: "used a NULL pointer (its address was 0)",  # set to 0 or NULL, or never set
    }.get(kind)
    if kind == c.CRS_FW_TRAP_MEMORY and recursed(text):
        what = "overflowed its call stack (runaway recursion)"

    if what is None:
        first = for_terminal(next((s.strip() for s in text.split("\n") if s.strip()), "the board stopped it"))
        return RunStatus.CRASHED, f"{lab_name} crashed ({first}) {place} {at}"
    why = ("; on the C28x an integer division by zero does not stop the board: it goes on with an undefined "
           "result" if kind == c.CRS_FW_TRAP_DIVIDE else "")
    return RunStatus.CRASHED, f"{lab_name} {what} {place} {at}{why}"
