"""Build a lab file (unmodified) into the firmware the board runs.

By default the lab becomes a WebAssembly module (:mod:`crslab.lab.firmware`): the lab file linked
with the framework's stand-ins, compiled by zig for wasm32, run by the board in a store of its own
(csrc/board/firmware_wasm.c). ``native`` (crslab debug, ``--sanitize``, ``--native``) instead links
the lab, the same stand-ins and the whole board into one shared object with the host C compiler
(``$CC``, else ``cc``, ``gcc`` or ``clang``; :mod:`crslab.lab.compiler`), which the worker loads.

Either way the lab is compiled as C11 (never a GNU dialect, so globals named ``gamma``, ``y0`` or
``j1`` do not clash with the C library's math declarations), a ``.cpp`` file holding C is compiled
as C, and the compiler runs contained (:mod:`crslab.lab.compile_process`: limits, its own process
group) in the compile sandbox (crslab/sandbox/compile_sandbox.py: it reads only the lab's folder,
crslab's headers and the compiler's own files, and writes only the build folder; reading anything
else is :class:`LabForbidden`). A lab whose globals do not fit the F28335's data memory, as the TI
linker would lay them out, does not build either (:func:`check_board_memory`). Builds are cached per
user by the content of the lab, of every board source, of the flags and by the compiler's identity.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from crslab import os_support, resources
from crslab.cache import CacheError, cache_dir
from crslab.framework_facts import DATA_RAM_END, DATA_RAM_START
from crslab.generations import Generation, detect
from crslab.lab import firmware, zig
from crslab.lab.c28x_memory import MemoryLayout, layout
from crslab.lab.compile_process import LabBuildError, LabForbidden, check_image, run_compiler
from crslab.lab.compiler import Compiler, CompilerMissing, find_compiler
from crslab.lab.includes import local_includes
from crslab.lab.lab_file import read_lab_file
from crslab.lab.variables import LabVariable, find_variables
from crslab.lab.watched import WatchedVar, find_watched
from crslab.sandbox.compile_sandbox import compiler_sandbox

CSRC = resources.path("csrc")
SHIM_INCLUDE = CSRC / "firmware" / "include"
KIN = CSRC / "kin"
BOARD = CSRC / "board"
PLANT = CSRC / "plant"
PORT = CSRC / "port"
FIRMWARE = CSRC / "firmware"
DEFAULT_LAB = CSRC / "labs" / "lab1_kinematics.c"
WASM_ONLY = {"firmware_wasm.c"}
"""Board sources of crslab._core alone (the native board is linked with a lab instead)."""
BOARD_SOURCES = (sorted(p for p in BOARD.glob("*.c") if p.name not in WASM_ONLY) + sorted(PLANT.glob("*.c"))
                 + sorted(PORT.glob("*.c")) + sorted(FIRMWARE.glob("*.c")) + sorted(KIN.glob("*.c")))
BOARD_HEADERS = (sorted(BOARD.glob("*.h")) + sorted(PLANT.glob("*.h")) + sorted(PORT.glob("*.h"))
                 + sorted(FIRMWARE.glob("*.h")) + sorted(KIN.glob("*.h")) + sorted(SHIM_INCLUDE.glob("*.h")))
BOARD_FOLDERS = [BOARD, PLANT, PORT]
"""The board's, the plant's and the port's C: a native build links them with the firmware."""

INCLUDES = ["-I", str(SHIM_INCLUDE), "-I", str(FIRMWARE), "-I", str(KIN),
            *(arg for folder in BOARD_FOLDERS for arg in ("-I", str(folder)))]
ERROR_LIMIT = ["-fmax-errors=50"]
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
TRAP_SOURCE = CSRC / "sandbox" / "trap.c"
TRAP_HEADERS = [CSRC / "sandbox" / "trap.h", *sorted(BOARD.glob("*.h")), *sorted(PORT.glob("*.h"))]
TRAP_FLAGS = ["-std=c11", "-O2", "-fPIC", "-Wall", "-Wextra", "-Werror", "-shared"]


@dataclass(frozen=True)
class LabBuild:
    """A built lab: its firmware image and what was learned from the source."""

    source: Path
    image: Path
    """The firmware: ``lab.wasm`` (WebAssembly), or ``lab.so`` (native: the lab linked with the board)."""
    generation: Generation
    """The framework generation the file was written for (its row; :func:`crslab.generations.detect`)."""
    sanitized: bool
    digest: str
    native: bool = False
    """Built natively (crslab debug, --sanitize, --native) rather than as WebAssembly."""
    watched: tuple[WatchedVar, ...] = field(default=())
    compiler: Compiler | None = None
    debug: bool = False
    """Built for a debugger: ``-O0 -g`` (``crslab debug``)."""
    break_when: str | None = None
    """The ``--break-when`` condition compiled in with the lab (``crs_debug_condition``), if any."""
    variables: tuple[LabVariable, ...] = field(default=())
    """Every global the file defines (laid out in C28x memory by crslab.lab.c28x_memory)."""
    renamed: tuple[str, ...] = field(default=())
    """Globals of the lab compiled under another name in its WebAssembly image, because the C
    library defines theirs (:func:`crslab.lab.firmware.clashing_symbols`)."""
    sized: tuple[str, ...] = field(default=())
    """The lab's globals in its WebAssembly image's size table, in the table's order
    (:func:`crslab.lab.firmware.unit_text`)."""
    trap_library: Path | None = None
    """Native builds: the run sandbox's SIGSYS handler (:func:`trap_library`), built here so that no
    worker ever compiles."""

    def image_name(self, name: str) -> str:
        """What the lab's global ``name`` is called in its image."""
        return firmware.RENAMED_PREFIX + name if name in self.renamed else name

    @property
    def printf_buffer_chars(self) -> int:
        """Characters the real board's serial_printf buffer holds for this framework generation
        (a line of this many or more overflows it)."""
        return self.generation.printf_buffer_chars

    @property
    def memory(self) -> MemoryLayout:
        """The lab's globals in the F28335's data memory, laid out as the TI linker would."""
        return layout(self.variables, self.generation, self.source.stem)

    @property
    def shared_object(self) -> Path:
        """The native build's shared object (the board and the lab)."""
        if not self.native:
            raise ValueError(f"{self.source.name} was built as WebAssembly, not as a shared object")
        return self.image


def text_memory(source_text: str, lab_name: str) -> MemoryLayout:
    """:attr:`LabBuild.memory` from a lab file's text alone: the layout depends on nothing else, so
    ``crslab map`` and ``crslab vars`` need no build."""
    return layout(find_variables(source_text), detect(source_text), lab_name)


def header_part(lab: Path, header: Path) -> bytes:
    """What a header the lab includes from its folder adds to the build's name: its path from the
    lab's folder and its bytes."""
    try:
        data = header.read_bytes()
    except OSError:
        data = b""
    name = os.path.relpath(header, lab.resolve().parent).encode()
    return len(name).to_bytes(8, "little") + name + len(data).to_bytes(8, "little") + data


def content_digest(parts: list[bytes]) -> str:
    """A short hash of ``parts`` (each length-prefixed), naming a cached build."""
    h = hashlib.sha256()
    for p in parts:
        h.update(len(p).to_bytes(8, "little"))
        h.update(p)
    return h.hexdigest()[:20]


def compiler() -> Compiler:
    """The host compiler native labs are built with; a missing one is a :class:`LabBuildError`
    saying how to install one."""
    try:
        return find_compiler()
    except CompilerMissing as exc:
        raise LabBuildError(str(exc)) from None


def _cache() -> Path:
    try:
        return cache_dir()
    except CacheError as exc:
        raise LabBuildError(str(exc)) from None


def check_board_memory(variables: list[LabVariable], generation: Generation, source: Path) -> None:
    """Refuse a lab whose globals, laid out as the TI linker would (16-bit words, the framework's
    sections), run past the F28335's data memory (``DATA_RAM_START`` to ``DATA_RAM_END``): the
    real board's link fails the same way."""
    placed = layout(variables, generation, source.stem).variables
    end = max((v.address + v.words for v in placed), default=DATA_RAM_START)
    if end > DATA_RAM_END:
        need_kb = (end - DATA_RAM_START) * 2 / 1024
        have_kb = (DATA_RAM_END - DATA_RAM_START) * 2 / 1024
        biggest = max(placed, key=lambda v: v.words)
        raise LabBuildError(f"{source.name} does not fit the board: its globals need {need_kb:,.0f} KB, the "
                            f"board has {have_kb:,.0f} KB for its data (the largest, {biggest.name}, takes "
                            f"{biggest.words * 2 / 1024:,.1f} KB)")


def _compiled(out: Path, argv: list[str], what: str) -> Path:
    """``out``, compiled by ``argv`` (without its ``-o``) unless it is there already: through a
    temporary name, so a build cut short or run beside another never leaves half a file."""
    if not out.exists():
        out.parent.mkdir(parents=True, exist_ok=True)
        tmp = out.with_suffix(f".{os.getpid()}.tmp")
        run_compiler([*argv, "-o", str(tmp)], what)
        tmp.replace(out)
    return out


def _own_c_dir(cache: Path, name: str, cc: Compiler, flags: list[str], inputs: list[Path]) -> Path:
    """The cache folder of one build of crslab's own C: named by the compiler's identity, the flags
    and the content of every input."""
    digest = content_digest([cc.identity.encode(), " ".join(flags).encode()]
                            + [p.read_bytes() for p in inputs])
    return cache / f"{name}-{digest}"


def _board_objects(cc: Compiler, sanitize: bool, cache: Path, debug: bool = False) -> list[Path]:
    """The native board, framework stand-ins and kinematics objects, built once per content,
    flags and compiler."""
    flags = BOARD_FLAGS + (SANITIZE_FLAGS if sanitize else []) + (DEBUG_BOARD_FLAGS if debug else [])
    out_dir = _own_c_dir(cache, "board", cc, flags, BOARD_SOURCES + BOARD_HEADERS)
    return [_compiled(out_dir / f"{src.parent.name}_{src.stem}.o",
                      [*cc.argv, *flags, *INCLUDES, "-c", str(src)], f"crslab's board source {src.name}")
            for src in BOARD_SOURCES]


def trap_library(cc: Compiler, cache: Path) -> Path:
    """The run sandbox's SIGSYS handler (``csrc/sandbox/trap.c``, :mod:`crslab.sandbox.trap` loads
    it), built once per content and compiler, like the board."""
    out_dir = _own_c_dir(cache, "sandbox", cc, TRAP_FLAGS, [TRAP_SOURCE, *TRAP_HEADERS])
    return _compiled(out_dir / "trap.so",
                     [*cc.argv, *TRAP_FLAGS, "-I", str(BOARD), "-I", str(PORT), str(TRAP_SOURCE)],
                     "crslab's sandbox trap")


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


def _build_wasm(src: Path, named_by: bytes, variables: list[LabVariable], cache: Path,
                sandboxed: bool) -> tuple[firmware.WasmImage, str]:
    """The WebAssembly firmware of ``src`` (cached, named by ``named_by``: the lab's bytes and its
    folder's headers it includes); returns (image, digest)."""
    try:
        firmware.prepare_zig()
        objects = firmware.firmware_objects(cache, content_digest)
    except (RuntimeError, zig.ZigMissing, OSError) as exc:
        raise LabBuildError(f"the WebAssembly compiler cannot be used: {exc}") from None
    globals_ = [v.name for v in variables if not v.static]
    # the path as given, not the folder: the module names the lab as given (prefix maps), so a lab
    # given by the same relative path builds the same module in any folder (crslab serve's sessions)
    digest = content_digest([named_by, src.suffix.encode(), str(src).encode(),
                             " ".join(firmware.LAB_FLAGS + firmware.LINK_FLAGS).encode(),
                             objects[0].parent.name.encode(), " ".join(globals_).encode()])
    out_dir = cache / f"wasm-{digest}"
    cached = firmware.WasmImage.load(out_dir)
    if cached is not None:
        return cached, digest
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=out_dir) as tmp:
        build_dir = Path(tmp)
        sandbox = compiler_sandbox([src], build_dir,
                                   [SHIM_INCLUDE, FIRMWARE, KIN, *BOARD_FOLDERS, objects[0].parent],
                                   compiler=(), run_dirs=[zig.zig_dir()],
                                   cache_dirs=[zig.zig_cache()]) if sandboxed else None
        built = firmware.build_module(src, globals_, objects, build_dir, sandbox)
        built.path.replace(out_dir / "lab.wasm")
        built.save(out_dir)
    image = firmware.WasmImage.load(out_dir)
    assert image is not None
    return image, digest


def _build_native(src: Path, named_by: bytes, flags: list[str], unit: str | None, break_when: str | None,
                  sanitize: bool, debug: bool, cache: Path, sandboxed: bool) -> tuple[Path, str, Compiler]:
    """The native shared object of ``src`` linked with the board (cached); returns (image, digest, cc)."""
    cc = compiler()
    objects = _board_objects(cc, sanitize, cache, debug)
    digest = content_digest([named_by, " ".join(flags).encode(), src.suffix.encode()]
                            + [o.parent.name.encode() for o in objects[:1]]  # it names the compiler
                            + ([unit.encode()] if unit is not None else [])
                            # a debugger finds the source by the path compiled into the build
                            + ([str(src.absolute()).encode()] if debug else []))
    out_dir = cache / f"lab-{digest}"
    so = out_dir / "lab.so"
    if not so.exists():
        out_dir.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=out_dir) as tmp:
            readable = [SHIM_INCLUDE, FIRMWARE, KIN, *BOARD_FOLDERS, objects[0].parent]
            sandbox = compiler_sandbox([src], Path(tmp), readable, compiler=cc.argv) if sandboxed else None
            obj = Path(tmp) / "lab.o"
            # compile the user's own path so the compiler's messages name the user's file and line
            # (absolute for a debugger, which then finds the source from any folder)
            compiled, what = (src.absolute() if debug else src), src.name
            if unit is not None:
                compiled = Path(tmp) / "break_when.c"
                compiled.write_text(unit)
                what = f"{src.name} with --break-when {break_when!r}"
            run_compiler([*cc.argv, *flags, *ERROR_LIMIT, *INCLUDES, "-x", "c", "-c", str(compiled), "-o",
                          str(obj)], what, sandbox)
            tmp_so = Path(tmp) / "lab.so"
            link_flags = [*os_support.SHARED_OBJECT_FLAGS, *(cc.sanitizer_link_flags() if sanitize else [])]
            try:
                run_compiler([*cc.argv, *link_flags, "-Wl,--no-undefined", "-o", str(tmp_so), str(obj),
                              *map(str, objects), *LINK_LIBS], f"{src.name} (link)", sandbox)
            except LabForbidden:
                raise
            except LabBuildError as exc:
                if "undefined reference to `" in exc.diagnostics:
                    text = exc.diagnostics.replace("undefined reference to `", "undefined symbol: ")
                    raise firmware.link_failure(src, text) from None
                raise
            check_image(tmp_so, src.name)
            tmp_so.replace(so)
    return so, digest, cc


def build_lab(source: Path | None = None, *, native: bool = False, sanitize: bool = False,
              cache: Path | None = None, sandboxed: bool = True, debug: bool = False,
              break_when: str | None = None) -> LabBuild:
    """Build ``source`` (default: crslab's Lab 1) into its firmware, cached in ``cache`` (default:
    the per-user cache, :func:`crslab.cache.cache_dir`): WebAssembly, unless ``native``,
    ``sanitize`` (ASan and UBSan) or ``debug`` (``crslab debug``: the lab ``-O0 -g``, the board
    with line information, and with ``break_when`` (a C expression) that condition as
    ``crs_debug_condition()``) ask for a native shared object. ``sandboxed`` compiles it in the
    compile sandbox (see :func:`crslab.sandbox.resolve`).

    Raises :class:`LabBuildError` for a missing file, a file that does not compile (or link, or
    fit the board's memory) or a missing compiler, and :class:`LabForbidden` when the sandboxed
    compiler was refused a file the lab names.
    """
    src = Path(source) if source is not None else DEFAULT_LAB
    text_bytes = read_lab_file(src)
    text = text_bytes.decode("utf-8", "replace")
    special, headers = local_includes(src)
    if special is not None:
        raise LabBuildError(f"{src.name} does not compile: {special}")
    # the headers the lab includes from its own folder name the build as much as the lab does
    named_by = text_bytes + b"".join(header_part(src, h) for h in headers)
    generation = detect(text)
    variables = find_variables(text)
    check_board_memory(variables, generation, src)
    debug = debug or break_when is not None
    native = native or sanitize or debug
    cache = cache if cache is not None else _cache()
    cc: Compiler | None = None
    renamed: tuple[str, ...] = ()
    sized: tuple[str, ...] = ()
    trap: Path | None = None
    if native:
        flags = LAB_FLAGS + (SANITIZE_FLAGS if sanitize else []) + (DEBUG_LAB_FLAGS if debug else [])
        unit = break_when_source(src, break_when) if break_when is not None else None
        image, digest, cc = _build_native(src, named_by, flags, unit, break_when, sanitize, debug, cache,
                                          sandboxed)
        trap = trap_library(cc, cache)
    else:
        wasm, digest = _build_wasm(src, named_by, variables, cache, sandboxed)
        image, renamed, sized = wasm.path, wasm.renamed, wasm.sized
    return LabBuild(source=src, image=image, generation=generation, sanitized=sanitize, digest=digest,
                    native=native, watched=tuple(find_watched(text)), compiler=cc, debug=debug,
                    break_when=break_when, variables=tuple(variables), renamed=renamed, sized=sized,
                    trap_library=trap)
