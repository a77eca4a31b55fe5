"""Where the board's widths change a result: the C28x (COFF ABI) has a 16-bit ``int``, a 32-bit
``long`` and a 32-bit ``double``, so ``300*300`` in an ``int``, a constant past 32767 stored in an
``int`` or compared with one, or a constant a 32-bit ``double`` cannot hold, gives another result
than a host's 32-bit ``int`` and 64-bit ``double`` would. crslab's WebAssembly board computes with
the C28x's widths (:mod:`crslab.lab.c28x_ir`), so there the check says where a lab's arithmetic
overflows or rounds on the board; a native build computes with the host's, so there it says where
its results differ from the board's.

For analysis only, the lab is compiled twice more with zig's clang (``crslab.lab.zig``), with the
same headers, the same diagnostics and no C library (an object file, then thrown away): once for
a target with the C28x's widths (AVR: int 16, long 32, double 32) and once for the host's
(x86-64). A diagnostic that only the first compile gives is a place where the board's result
differs; each is reported with its file and line. Nothing is linked or run, and the lab's own
build is untouched.

``crslab sim`` runs the check on a lab's first run (per content: a result is kept in the cache),
``crslab grade`` on every submission, into its report; ``--no-c28x-check`` turns it off.

>>> [f] = parse_diagnostics("lab.c:3:15: warning: overflow in expression; result is 24'464 with type "
...                         "'int' [-Winteger-overflow]\\n3 | int big = 300 * 300;\\n")
>>> f.file, f.line, f.flag, f.message
('lab.c', 3, 'integer-overflow', "overflow in expression; result is 24464 with type 'int'")
"""

from __future__ import annotations

import hashlib
import json
import re
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

from crslab import resources
from crslab.cache import CacheError, cache_dir, subfolder
from crslab.lab.c89_habits import lab_flags
from crslab.lab.compile_process import (
    LabBuildError,
    PrivateBuild,
    same_answer,
    start_sandboxed,
    visible_files,
)
from crslab.lab.lab_file import read_lab_file

BOARD_TARGET = ["--target=avr-freestanding", "-mmcu=atmega2560"]
"""A target whose C widths are the C28x's: int 16 bits, long 32, double 32."""
HOST_TARGET = ["--target=x86_64-freestanding"]
"""The host's widths (int 32, long 64, double 64), compiled the same way to tell what differs."""
DIAGNOSTICS = ["integer-overflow", "constant-conversion", "implicit-const-int-float-conversion",
               "literal-range", "tautological-constant-out-of-range-compare", "shift-overflow",
               "shift-count-overflow", "bitfield-constant-conversion", "implicit-int-float-conversion"]
"""The diagnostics that say a value changes (overflow, truncation, precision)."""
POINTER_DIAGNOSTICS = ["implicit-function-declaration", "int-conversion"]
"""What tells that an undeclared function's result lands in a pointer (:func:`lost_pointers`)."""
FLAGS = ["-std=c11", "-c", "-nostdlib", "-ffreestanding", "-x", "c", "-Wno-everything",
         *(f"-W{d}" for d in DIAGNOSTICS + POINTER_DIAGNOSTICS), *lab_flags("clang")[1:],
         "-fno-color-diagnostics", "-fno-caret-diagnostics", "-Wno-unused-command-line-argument"]
"""The check's flags: the C89 habits build as the lab's own build takes them (as warnings), with
the compiler's built-in knowledge of the C library off (``-ffreestanding``), as on the board, where
an undeclared ``malloc`` returns an ``int``."""
TIMEOUT_S = 60.0
_LINE = re.compile(r"^(?P<file>.+?):(?P<line>\d+):\d+: warning: (?P<message>.*?) \[-W(?P<flag>[\w-]+)\]$",
                   re.MULTILINE)
WIDTHS = "on the C28x int is 16 bits, long 32 and double 32"


@dataclass(frozen=True)
class Finding:
    """One place where the board's result differs: the file and line, and the compiler's words."""

    file: str
    line: int
    message: str
    flag: str

    def describe(self) -> str:
        """One line for a person.

        >>> Finding("lab.c", 3, "overflow in expression; result is 24464 with type 'int'", "x").describe()
        "lab.c:3: overflow in expression; result is 24464 with type 'int'"
        """
        return f"{self.file}:{self.line}: {self.message}"


@dataclass(frozen=True)
class C28xReport:
    """The check's outcome: its findings, or why it could not run (``skipped``)."""

    findings: tuple[Finding, ...] = ()
    skipped: str = ""

    def lines(self, native: bool = False) -> list[str]:
        """What is said about it, one line each (nothing when all is well); ``native``: about a native
        build, which computes with the host's widths.

        >>> r = C28xReport((Finding("lab.c", 3, "overflow", "integer-overflow"),))
        >>> r.lines()[0]
        "warning: 1 place where the C28x's widths change a result (on the C28x int is 16 bits, long 32 \
and double 32; crslab's WebAssembly board computes with them too):"
        """
        if self.skipped:
            return [f"note: the C28x arithmetic check did not run: {self.skipped}"]
        if not self.findings:
            return []
        places = f"{len(self.findings)} place{'s' if len(self.findings) != 1 else ''}"
        head = (f"warning: {places} where the board's arithmetic gives another result than this native build "
                f"({WIDTHS}; here 32, 64, 64):" if native else
                f"warning: {places} where the C28x's widths change a result ({WIDTHS}; crslab's WebAssembly "
                "board computes with them too):")
        return [head, *(f"  {f.describe()}" for f in self.findings)]


def parse_diagnostics(text: str) -> list[Finding]:
    """The warnings in a compiler's output (digit separators such as ``24'464`` removed)."""
    out = []
    for m in _LINE.finditer(text):
        message = re.sub(r"(?<=\d)'(?=\d)", "", m["message"])
        out.append(Finding(Path(m["file"]).name, int(m["line"]), message, m["flag"]))
    return out


def board_only(board: Sequence[Finding], host: Sequence[Finding]) -> list[Finding]:
    """The board compile's findings that the host compile does not give at the same line.

    >>> a, b = Finding("l.c", 3, "x", "integer-overflow"), Finding("l.c", 9, "y", "integer-overflow")
    >>> board_only([a, b], [Finding("l.c", 9, "z", "integer-overflow")]) == [a]
    True
    """
    seen = {(f.file, f.line, f.flag) for f in host}
    unique: list[Finding] = []
    for f in board:
        if (f.file, f.line, f.flag) not in seen and f not in unique:
            unique.append(f)
    return unique


_CALLED = re.compile(r"call to undeclared function '(\w+)'")


def lost_pointers(board: Sequence[Finding]) -> list[Finding]:
    """The places where the board compile stores the result of a function it has no declaration of
    in a pointer (an undeclared ``malloc`` without ``<stdlib.h>``): C89 makes the result an ``int``,
    which the C28x returns in AL, the accumulator's low 16 bits, while the function returns its
    pointer in XAR4 (SPRU514's calling convention, docs/framework.md section 9); so the caller
    stores whatever AL held, not the pointer.

    >>> [f] = lost_pointers([Finding("l.c", 7, "call to undeclared function 'malloc'; ISO C99 ...",
    ...                             "implicit-function-declaration"),
    ...                     Finding("l.c", 7, "incompatible integer to pointer conversion ...",
    ...                             "int-conversion")])
    >>> print(f.describe())  # doctest: +NORMALIZE_WHITESPACE
    l.c:7: malloc() has no declaration before this line, so the board takes it to return an int and
    reads AL, where the C28x returns an int, while malloc() returns its pointer in XAR4: the pointer
    stored here is whatever AL held, not malloc()'s; declare it (its header)
    """
    called: dict[tuple[str, int], str] = {}
    for f in board:
        m = _CALLED.search(f.message) if f.flag == "implicit-function-declaration" else None
        if m is not None:
            called.setdefault((f.file, f.line), m.group(1))
    out: list[Finding] = []
    for f in board:
        name = called.get((f.file, f.line))
        if f.flag == "int-conversion" and "integer to pointer" in f.message and name is not None:
            cut = Finding(f.file, f.line, f"{name}() has no declaration before this line, so the board "
                          "takes it to return an int and reads AL, where the C28x returns an int, while "
                          f"{name}() returns its pointer in XAR4: the pointer stored here is whatever AL "
                          f"held, not {name}()'s; declare it (its header)", "pointer-lost")
            if cut not in out:
                out.append(cut)
    return out


def include_dirs() -> list[str]:
    """The C library's headers as the lab's build with the C28x's widths sees them (no C library
    behind them: nothing is linked), then those a lab is built with."""
    csrc = resources.path("csrc")
    return ["-I", str(csrc / "firmware" / "c28x"), "-I", str(csrc / "firmware" / "include"),
            "-I", str(csrc / "kin")]


class C28xCheck:
    """The two compiles of one lab, started at once (they run while the lab runs) and awaited by
    :meth:`report`: each in a private build of its own (a copy of the lab's folder's allowed files,
    the overlay that shows the compiler nothing else: :mod:`crslab.lab.compile_process`), never on
    the lab's own folder. ``sandboxed`` runs them in the compile sandbox too; ``text``: the lab's
    text as the caller read it (None: read here); ``alone``: the lab without its folder's files (a
    class's submission, as grade builds it)."""

    def __init__(self, lab: Path, *, sandboxed: bool = True, text: bytes | None = None,
                 alone: bool = False) -> None:
        self.lab = Path(lab).absolute()
        self._builds: list[PrivateBuild] = []
        self._procs: list = []
        self._skipped = ""
        try:
            from crslab.lab.zig import zig_cc, zig_dir, zig_environment

            argv = zig_cc()
            text = read_lab_file(self.lab) if text is None else text
            for target in (BOARD_TARGET, HOST_TARGET):
                private = PrivateBuild(self.lab, text, alone=alone)
                self._builds.append(private)
                work = private.folder
                for sub in ("cache", "global"):
                    (work / sub).mkdir()
                env = zig_environment(work / "cache")
                env["ZIG_GLOBAL_CACHE_DIR"] = str(work / "global")  # nothing of the lab's is kept
                overlay = visible_files(work, [work, resources.path("csrc"), zig_dir() / "lib"])
                box = None
                if sandboxed:
                    from crslab.sandbox.compile_sandbox import compiler_sandbox

                    box = compiler_sandbox([], work, [resources.path("csrc"), zig_dir()], compiler=argv)
                self._procs.append(start_sandboxed(
                    [*argv, *target, *FLAGS, "-ivfsoverlay", str(overlay), *include_dirs(),
                     "-iquote", str(private.source), str(private.copy), "-o", str(work / "lab.o")],
                    box, env=env, cwd=work, reaper=private.reaper))
        except (ImportError, FileNotFoundError, OSError) as exc:
            self._skipped = f"zig cannot be run ({exc})"
        except LabBuildError as exc:
            self._skipped = str(exc)

    def report(self) -> C28xReport:
        """Wait for both compiles and compare them."""
        try:
            if self._skipped:
                return C28xReport(skipped=self._skipped)
            outputs = []
            for proc in self._procs:
                r = proc.wait(TIMEOUT_S)
                if r.timed_out:
                    return C28xReport(skipped=f"zig took longer than {TIMEOUT_S:.0f} s")
                err = same_answer(r.stderr)
                outputs.append(err)
                if r.returncode != 0 and "error:" in err:
                    first = next(line for line in err.splitlines() if "error:" in line)
                    return C28xReport(skipped=f"the lab does not compile without a C library: "
                                              f"{first.split('error:', 1)[1].strip()}")
            board, host = (parse_diagnostics(o) for o in outputs)
            widths = [f for f in board if f.flag in DIAGNOSTICS]
            return C28xReport(tuple(lost_pointers(board) + board_only(widths, host)))
        finally:
            self.close()

    def close(self) -> None:
        """Stop what still runs (zig and the clang it runs: the whole group) and remove the private
        builds (again: nothing)."""
        for proc in self._procs:
            proc.kill()
        self._procs = []
        for private in self._builds:
            private.close()
        self._builds = []


def check_lab(lab: Path, *, sandboxed: bool = True, text: bytes | None = None,
              alone: bool = False) -> C28xReport:
    """Run the check on ``lab`` (see :class:`C28xCheck`) and wait for it."""
    return C28xCheck(lab, sandboxed=sandboxed, text=text, alone=alone).report()


def _key(lab: Path) -> str:
    h = hashlib.sha256(Path(lab).read_bytes())
    for header in [*sorted((resources.path("csrc") / "firmware" / "c28x").rglob("*.h")),
                   *sorted((resources.path("csrc") / "firmware" / "include").glob("*.h"))]:
        h.update(header.read_bytes())
    h.update(" ".join([*BOARD_TARGET, *FLAGS]).encode())
    return h.hexdigest()[:20]


def first_run_check(lab: Path, *, sandboxed: bool = True) -> C28xCheck | None:
    """The check of ``lab`` when this content has not been checked before (``crslab sim`` says it
    on a lab's first run only), else None; :func:`remember` records that it was shown."""
    try:
        if (cache_dir() / "c28x" / f"{_key(lab)}.json").exists():
            return None
    except (CacheError, OSError):
        return None
    return C28xCheck(lab, sandboxed=sandboxed)


def remember(lab: Path, report: C28xReport) -> None:
    """Record that ``lab``'s report was given (or that the check cannot run on it)."""
    try:
        folder = subfolder(cache_dir(), "c28x")
        kept = {"skipped": report.skipped, "findings": [asdict(f) for f in report.findings]}
        (folder / f"{_key(lab)}.json").write_text(json.dumps(kept))
    except (CacheError, OSError):
        pass
