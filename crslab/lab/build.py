"""Compile a lab file (unmodified) with the host C compiler into a shared object with the
emulated board.

The compiler is ``$CC``, else ``cc``, ``gcc`` or ``clang`` (:mod:`crslab.lab.compiler`). The lab is
compiled as C11 (never a GNU dialect, so globals named ``gamma``, ``y0`` or ``j1`` do not clash
with glibc's math declarations), a ``.cpp`` file holding C is compiled as C, and the object is
linked so lab globals named like libc functions (``time``, ``index``, ``step``) bind to the
lab's own definitions (:data:`crslab.os_support.SHARED_OBJECT_FLAGS`). The board's sources come
from the installed package (:mod:`crslab.resources`). Builds are cached per user by the content
of the lab, of every board source, of the flags and by the compiler's identity, so a second run
starts at once.

The lab is compiled and linked inside the compile sandbox (crslab/sandbox/compile_sandbox.py):
the compiler reads only the lab's folder, crslab's headers and objects and the compiler's own
files, and writes only the build folder; reading anything else is :class:`LabForbidden`.
"""

from __future__ import annotations

import hashlib
import os
import re
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from crslab import os_support, resources
from crslab.cache import CacheError, cache_dir
from crslab.framework_facts import GEN_A, GEN_B, printf_buffer_chars
from crslab.lab.compiler import Compiler, CompilerMissing, find_compiler
from crslab.lab.lab_file import lab_file_problem
from crslab.lab.variables import LabVariable, find_variables
from crslab.lab.watched import WatchedVar, find_watched
from crslab.sandbox.compile_sandbox import CompilerSandbox, compiler_sandbox, forbidden_read

CSRC = resources.path("csrc")
SHIM_INCLUDE = CSRC / "board" / "include"
KIN = CSRC / "kin"
SIM = CSRC / "sim"
DEFAULT_LAB = CSRC / "labs" / "lab1_kinematics.c"
BOARD_SOURCES = sorted(SIM.glob("*.c")) + sorted(KIN.glob("*.c"))
BOARD_HEADERS = sorted(SIM.glob("*.h")) + sorted(KIN.glob("*.h")) + sorted(SHIM_INCLUDE.glob("*.h"))

COMPILE_TIMEOUT_S = 60.0
INCLUDES = ["-I", str(SHIM_INCLUDE), "-I", str(KIN), "-I", str(SIM)]
LAB_FLAGS = ["-std=c11", "-O2", "-fPIC", "-w", "-fno-common"]
BOARD_FLAGS = ["-std=c11", "-O2", "-fPIC", "-Wall", "-Wextra", "-Werror", "-fno-math-errno"]
# ASan finds out-of-bounds reads and writes (and says which); UBSan the rest (overflow,
# misalignment, bad shifts), so UBSan's own array-bounds and object-size checks are left to ASan.
SANITIZE_FLAGS = ["-fsanitize=address,undefined", "-fno-sanitize=bounds,object-size",
                  "-fno-omit-frame-pointer", "-g", "-O1"]
# crslab debug: the lab unoptimized with full debug information (after the flags above: -O0
# wins), so every line and variable is where the source says; the board keeps -O2 and gains
# line information, so stepping out of lab() shows the framework's own C, as CCS shows its source.
DEBUG_LAB_FLAGS = ["-O0", "-g", "-fno-omit-frame-pointer"]
DEBUG_BOARD_FLAGS = ["-g"]
LINK_LIBS = os_support.MATH_LIBS

_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.MULTILINE)


class LabBuildError(Exception):
    """The lab could not be built; ``diagnostics`` holds the compiler's own messages."""

    def __init__(self, message: str, diagnostics: str = "") -> None:
        super().__init__(message)
        self.diagnostics = diagnostics


class LabForbidden(LabBuildError):
    """The sandboxed compiler was refused a file the lab names (an ``#include`` of a path
    outside the lab's folder, a symbolic link out of it, an ``.incbin``): ``path`` is that file."""

    def __init__(self, message: str, diagnostics: str, path: str) -> None:
        super().__init__(message, diagnostics)
        self.path = path


@dataclass(frozen=True)
class LabBuild:
    """A compiled lab: the shared object and what was learned from the source."""

    source: Path
    shared_object: Path
    generation: int
    sanitized: bool
    digest: str
    watched: tuple[WatchedVar, ...] = field(default=())
    compiler: Compiler | None = None
    debug: bool = False
    """Built for a debugger: ``-O0 -g`` (``crslab debug``)."""
    break_when: str | None = None
    """The ``--break-when`` condition compiled in with the lab (``crs_debug_condition``), if any."""
    variables: tuple[LabVariable, ...] = field(default=())
    """Every global the file defines (laid out in C28x memory by crslab.host_tools.c28x_memory)."""

    @property
    def printf_buffer_chars(self) -> int:
        """Characters the real board's serial_printf buffer holds for this framework generation
        (a line of this many or more overflows it)."""
        return printf_buffer_chars(self.generation)


def detect_generation(source_text: str) -> int:
    """Which framework the file was written for, from its includes.

    >>> detect_generation('#include "F28335Serial.h"')
    2
    >>> detect_generation('#include <coecsl.h>')
    1
    """
    includes = set(_INCLUDE.findall(source_text))
    return GEN_B if "F28335Serial.h" in includes and "coecsl.h" not in includes else GEN_A


def content_digest(parts: list[bytes]) -> str:
    """A short hash of ``parts`` (each length-prefixed), naming a cached build."""
    h = hashlib.sha256()
    for p in parts:
        h.update(len(p).to_bytes(8, "little"))
        h.update(p)
    return h.hexdigest()[:20]


def compiler() -> Compiler:
    """The compiler labs are built with; a missing one is a :class:`LabBuildError` saying how to
    install one."""
    try:
        return find_compiler()
    except CompilerMissing as exc:
        raise LabBuildError(str(exc)) from None


def _cache() -> Path:
    try:
        return cache_dir()
    except CacheError as exc:
        raise LabBuildError(str(exc)) from None


def run_compiler(cc: Compiler, args: list[str], what: str, sandbox: CompilerSandbox | None = None) -> None:
    """Run ``cc`` with ``args`` (inside ``sandbox`` when given); a failure is a LabBuildError."""
    rules, extra = None, {}
    if sandbox is not None:
        try:
            rules = sandbox.ruleset()
        except OSError as exc:  # Landlock missing: the caller should not have asked for the sandbox
            raise LabBuildError(f"the compile sandbox cannot be set up ({exc}); --no-sandbox compiles "
                                "without it") from None
        extra = {"preexec_fn": sandbox.preexec(rules.fd), "env": sandbox.environment()}
    try:
        r = subprocess.run([*cc.argv, *args], capture_output=True, text=True, timeout=COMPILE_TIMEOUT_S,
                           **extra)  # type: ignore[call-overload]
    except subprocess.TimeoutExpired:
        raise LabBuildError(f"{what}: {cc.name} took longer than {COMPILE_TIMEOUT_S:.0f} s") from None
    except OSError as exc:
        raise LabBuildError(f"{cc.name} cannot be run ({exc.strerror})") from None
    finally:
        if rules is not None:
            rules.close()
    if r.returncode != 0:
        refused = forbidden_read(r.stderr) if sandbox is not None else None
        if refused:
            shown = f"{refused} (a symbolic link to {os.path.realpath(refused)})" \
                if os.path.islink(refused) else refused
            raise LabForbidden(f"{what} was stopped by the sandbox: it tried to read {shown} while "
                               "compiling (a lab may read only its own folder, crslab's headers and the "
                               "compiler's files)", r.stderr, refused)
        raise LabBuildError(f"{what} does not compile", r.stderr)


def _board_objects(cc: Compiler, sanitize: bool, cache: Path, debug: bool = False) -> list[Path]:
    """The board, framework and kinematics objects, built once per content, flags and compiler."""
    flags = BOARD_FLAGS + (SANITIZE_FLAGS if sanitize else []) + (DEBUG_BOARD_FLAGS if debug else [])
    digest = content_digest([cc.identity.encode(), " ".join(flags).encode()]
                     + [p.read_bytes() for p in BOARD_SOURCES + BOARD_HEADERS])
    out_dir = cache / f"board-{digest}"
    objects = [out_dir / f"{p.parent.name}_{p.stem}.o" for p in BOARD_SOURCES]
    if all(o.exists() for o in objects):
        return objects
    out_dir.mkdir(parents=True, exist_ok=True)
    for src, obj in zip(BOARD_SOURCES, objects):
        tmp = obj.with_suffix(f".{os.getpid()}.tmp")
        run_compiler(cc, [*flags, *INCLUDES, "-c", str(src), "-o", str(tmp)],
                     f"crslab's board source {src.name}")
        tmp.replace(obj)
    return objects


def break_when_source(lab: Path, condition: str) -> str:
    """The translation unit of a ``--break-when`` build: the lab file itself and the condition as
    a function of it, so the condition sees the lab's globals (static ones too) with their own
    types, and the compiler checks it (its messages name ``--break-when``).

    >>> print(break_when_source(Path("/labs/lab1.c"), "mycount > 3"))
    #include "/labs/lab1.c"
    int crs_debug_condition(int error) { return (
    #line 1 "--break-when"
    mycount > 3
    ) != 0; }
    <BLANKLINE>
    """
    if "\n" in condition or "\r" in condition:
        raise LabBuildError("--break-when: the condition must be one line")
    quoted = str(lab.absolute()).replace("\\", "\\\\").replace('"', '\\"')
    return (f'#include "{quoted}"\nint crs_debug_condition(int error) {{ return (\n#line 1 "--break-when"\n'
            f"{condition}\n) != 0; }}\n")


def build_lab(source: Path | None = None, *, sanitize: bool = False, cache: Path | None = None,
              sandboxed: bool = True, debug: bool = False, break_when: str | None = None) -> LabBuild:
    """Compile ``source`` (default: crslab's Lab 1) and link it with the board; cached in
    ``cache`` (default: the per-user cache, :func:`crslab.cache.cache_dir`). ``sandboxed``
    compiles it in the compile sandbox (see :func:`crslab.sandbox.resolve`). ``debug`` builds it
    for a debugger (``crslab debug``): the lab ``-O0 -g``, the board with line information, and
    with ``break_when`` (a C expression) that condition as ``crs_debug_condition()``.

    Raises :class:`LabBuildError` for a missing file, a file that does not compile or a missing
    compiler, and :class:`LabForbidden` when the sandboxed compiler was refused a file the lab
    names.
    """
    src = Path(source) if source is not None else DEFAULT_LAB
    problem = lab_file_problem(src)
    if problem:
        raise LabBuildError(problem)
    try:
        text_bytes = src.read_bytes()
    except OSError as exc:
        raise LabBuildError(f"{src}: cannot be read ({exc.strerror})") from None
    text = text_bytes.decode("utf-8", "replace")
    generation = detect_generation(text)
    debug = debug or break_when is not None
    flags = LAB_FLAGS + (SANITIZE_FLAGS if sanitize else []) + (DEBUG_LAB_FLAGS if debug else [])
    unit = break_when_source(src, break_when) if break_when is not None else None
    cc = compiler()
    cache = cache if cache is not None else _cache()
    objects = _board_objects(cc, sanitize, cache, debug)
    digest = content_digest([text_bytes, " ".join(flags).encode(), src.suffix.encode()]
                            + [o.parent.name.encode() for o in objects[:1]]  # it names the compiler
                            + ([unit.encode()] if unit is not None else [])
                            # a debugger finds the source by the path compiled into the build
                            + ([str(src.absolute()).encode()] if debug else []))
    out_dir = cache / f"lab-{digest}"
    so = out_dir / "lab.so"
    if not so.exists():
        out_dir.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=out_dir) as tmp:
            sandbox = compiler_sandbox([src], Path(tmp), [SHIM_INCLUDE, KIN, SIM, objects[0].parent],
                                       compiler=cc.argv) if sandboxed else None
            obj = Path(tmp) / "lab.o"
            # compile the user's own path so the compiler's messages name the user's file and line
            # (absolute for a debugger, which then finds the source from any folder)
            compiled, what = (src.absolute() if debug else src), src.name
            if unit is not None:
                compiled = Path(tmp) / "break_when.c"
                compiled.write_text(unit)
                what = f"{src.name} with --break-when {break_when!r}"
            run_compiler(cc, [*flags, *INCLUDES, "-x", "c", "-c", str(compiled), "-o", str(obj)], what,
                         sandbox)
            tmp_so = Path(tmp) / "lab.so"
            link_flags = [*os_support.SHARED_OBJECT_FLAGS, *(cc.sanitizer_link_flags() if sanitize else [])]
            run_compiler(cc, [*link_flags, "-o", str(tmp_so), str(obj), *map(str, objects), *LINK_LIBS],
                         f"{src.name} (link)", sandbox)
            tmp_so.replace(so)
    if sandboxed:  # the worker's SIGSYS trap, built here so that no worker ever compiles
        from crslab.sandbox.trap import helper_library

        helper_library()
    return LabBuild(source=src, shared_object=so, generation=generation, sanitized=sanitize, digest=digest,
                    watched=tuple(find_watched(text)), compiler=cc, debug=debug, break_when=break_when,
                    variables=tuple(find_variables(text)))
