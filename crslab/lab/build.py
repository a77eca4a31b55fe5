"""Build a lab file (unmodified) into the firmware the board runs.

By default the lab becomes a WebAssembly module (:mod:`crslab.lab.firmware`): the lab file linked
with the framework's stand-ins, compiled by zig for wasm32, run by the board in a store of its own
(csrc/board/firmware_wasm.c). ``native`` (crslab debug, ``--sanitize``, ``--native``) instead links
the lab, the same stand-ins and the whole board into one shared object with the host C compiler
(``$CC``, else ``cc``, ``gcc`` or ``clang``; :mod:`crslab.lab.compiler`), which the worker loads.

Either way the lab is compiled as C11 (never a GNU dialect, so globals named ``gamma``, ``y0`` or
``j1`` do not clash with the C library's math declarations), a ``.cpp`` file holding C is compiled
as C, and the compiler runs contained (:mod:`crslab.lab.compile_process`: a private copy of the
lab's folder's allowed files, limits, its own process group, a reaper) in the compile sandbox
(crslab/sandbox/compile_sandbox.py: it reads only that copy, crslab's headers and the compiler's own
files, and writes only the build folder; a file it may not read is "not there", as a missing one). A
lab whose globals do not fit the F28335's data memory, as the TI linker would lay them out, does not
build either (:func:`check_board_memory`). Builds are cached per user (each sealed: a file planted in
the cache is not loaded), named by the lab's text, by what the compiler read of the lab's folder and
the names in it (the cache itself left out, when it lies in that folder), by the flags and by the
compiler's identity.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from crslab import os_support, resources
from crslab.cache import (
    CacheError,
    cache_dir,
    is_sealed,
    private_file,
    read_sealed,
    seal_into_place,
    subfolder,
    unsafe_reason,
    write_sealed,
)
from crslab.framework_facts import DATA_RAM_END, DATA_RAM_START
from crslab.generations import Generation, detect
from crslab.lab import firmware, zig
from crslab.lab.c28x_memory import MemoryLayout, layout
from crslab.lab.c89_habits import habit_warnings, lab_flags
from crslab.lab.compile_process import (
    LabBuildError,
    LabForbidden,
    PrivateBuild,
    allowed_files,
    check_image,
    dependencies,
    folder_listing,
    run_compiler,
)
from crslab.lab.compiler import Compiler, CompilerMissing, find_compiler
from crslab.lab.entry_points import EntryPointError, entry_calls
from crslab.lab.includes import header_texts, local_includes, own_variables
from crslab.lab.lab_file import read_lab_file
from crslab.lab.variables import LabVariable, find_variables, variables_of_files
from crslab.lab.watched import WatchedVar, watched_of
from crslab.sandbox.compile_sandbox import compiler_sandbox

CSRC = resources.path("csrc")
SHIM_INCLUDE = CSRC / "firmware" / "include"
KIN = CSRC / "kin"
BOARD = CSRC / "board"
PLANT = CSRC / "plant"
PORT = CSRC / "port"
FIRMWARE = CSRC / "firmware"
DEFAULT_LAB = CSRC / "labs" / "lab1_kinematics.c"


def wasm_port_only(source: Path) -> bool:
    """Whether a board source is the WebAssembly port's (``firmware_wasm*.c``): crslab._core's
    alone, the native board is linked with a lab instead.

    >>> wasm_port_only(Path("firmware_wasm_watchdog.c")), wasm_port_only(Path("tick.c"))
    (True, False)
    """
    return source.name.startswith("firmware_wasm")


BOARD_SOURCES = (sorted(p for p in BOARD.glob("*.c") if not wasm_port_only(p)) + sorted(PLANT.glob("*.c"))
                 + sorted(PORT.glob("*.c")) + sorted(FIRMWARE.glob("*.c")) + sorted(KIN.glob("*.c")))
BOARD_HEADERS = (sorted(BOARD.glob("*.h")) + sorted(PLANT.glob("*.h")) + sorted(PORT.glob("*.h"))
                 + sorted(FIRMWARE.glob("*.h")) + sorted(KIN.glob("*.h")) + sorted(SHIM_INCLUDE.glob("*.h")))
BOARD_FOLDERS = [BOARD, PLANT, PORT]
"""The board's, the plant's and the port's C: a native build links them with the firmware."""

INCLUDES = ["-I", str(SHIM_INCLUDE), "-I", str(FIRMWARE), "-I", str(KIN),
            *(arg for folder in BOARD_FOLDERS for arg in ("-I", str(folder)))]
ERROR_LIMIT = ["-fmax-errors=50"]
LAB_FLAGS = ["-std=c11", "-O0", "-fPIC", "-fno-common", "-fno-finite-loops", "-ffp-contract=off"]
"""The lab's flags: the optimisation off, as the board's builds (crslab.lab.firmware.OPTIMISATION;
``--sanitize`` needs ``-O1``, where a loop that waits for a global must still spin); the C89
habits' (:func:`crslab.lab.c89_habits.lab_flags`) follow them."""
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
NATIVE_RECIPE = b"unit named as the lab"
"""How a native build compiles the lab (part of its name): a build made another way (an older
crslab's) is not this one."""
TRAP_SOURCE = CSRC / "sandbox" / "trap.c"
TRAP_HEADERS = [CSRC / "sandbox" / "trap.h", *sorted(BOARD.glob("*.h")), *sorted(PLANT.glob("*.h")),
                *sorted(PORT.glob("*.h")), KIN / "traj_profiles.h"]
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
    memory: MemoryLayout = field(default=MemoryLayout((), ()))
    """The lab's globals in the F28335's data memory, laid out as the TI linker would (once, when
    the lab is built: the build checks it fits, the worker points the board's table at it, the map
    is written from it)."""
    renamed: tuple[str, ...] = field(default=())
    """Globals of the lab compiled under another name in its WebAssembly image, because the C
    library defines theirs (:func:`crslab.lab.firmware.clashing_symbols`)."""
    sized: tuple[str, ...] = field(default=())
    """The lab's globals in its WebAssembly image's size table, in the table's order
    (:func:`crslab.lab.firmware.unit_text`)."""
    trap_library: Path | None = None
    """Native builds: the run sandbox's SIGSYS handler (:func:`trap_library`), built here so that no
    worker ever compiles."""
    habits: tuple[str, ...] = field(default=())
    """The C89 habits the lab was built with, one line each saying what the board does
    (:mod:`crslab.lab.c89_habits`)."""

    def image_name(self, name: str) -> str:
        """What the lab's global ``name`` is called in its image."""
        return firmware.RENAMED_PREFIX + name if name in self.renamed else name

    @property
    def printf_buffer_chars(self) -> int:
        """Characters the real board's serial_printf buffer holds for this framework generation
        (a line of this many or more overflows it)."""
        return self.generation.printf_buffer_chars

    @property
    def shared_object(self) -> Path:
        """The native build's shared object (the board and the lab)."""
        if not self.native:
            raise ValueError(f"{self.source.name} was built as WebAssembly, not as a shared object")
        return self.image


def text_memory(source_text: str, lab_name: str) -> MemoryLayout:
    """:attr:`LabBuild.memory` of a lab file that includes no header of its own, from its text."""
    return layout(find_variables(source_text), detect(source_text), lab_name)


def lab_memory(lab: Path, source_text: str) -> MemoryLayout:
    """:attr:`LabBuild.memory` from a lab file's text (``source_text``) and its own headers' alone:
    the layout depends on nothing else, so ``crslab map`` and ``crslab vars`` need no build."""
    return layout(own_variables(lab, source_text), detect(source_text), lab.stem)


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


def _subfolder(cache: Path, *names: str) -> Path:
    """A folder of the cache, checked as it is used (:func:`crslab.cache.subfolder`); one that
    cannot be used is one line (:class:`LabBuildError`)."""
    try:
        return subfolder(cache, *names)
    except CacheError as exc:
        raise LabBuildError(str(exc)) from None


def check_board_memory(memory: MemoryLayout, source: Path) -> None:
    """Refuse a lab whose globals, laid out as the TI linker would (16-bit words, the framework's
    sections: ``memory``), run past the F28335's data memory (``DATA_RAM_START`` to
    ``DATA_RAM_END``): the real board's link fails the same way."""
    placed = memory.variables
    end = max((v.address + v.words for v in placed), default=DATA_RAM_START)
    if end > DATA_RAM_END:
        need_kb = (end - DATA_RAM_START) * 2 / 1024
        have_kb = (DATA_RAM_END - DATA_RAM_START) * 2 / 1024
        biggest = max(placed, key=lambda v: v.words)
        raise LabBuildError(f"{source.name} does not fit the board: its globals need {need_kb:,.0f} KB, the "
                            f"board has {have_kb:,.0f} KB for its data (the largest, {biggest.name}, takes "
                            f"{biggest.words * 2 / 1024:,.1f} KB)")


def _compiled(out: Path, argv: list[str], what: str) -> Path:
    """``out`` (in a folder of the cache, :func:`crslab.cache.subfolder`), compiled by ``argv``
    (without its ``-o``) unless this user's build sealed it there already: into a private file of
    its own, then sealed and renamed into place (:func:`crslab.cache.seal_into_place`), so a build
    cut short or run beside another never leaves half a file, and what is sealed is what it wrote."""
    if not is_sealed(out):
        fd, part = private_file(out.parent, out.name)
        os.close(fd)
        try:
            run_compiler([*argv, "-o", str(part)], what)
            seal_into_place(part, out, part.read_bytes())
        finally:
            part.unlink(missing_ok=True)
    return out


def _own_c_dir(cache: Path, name: str, cc: Compiler, flags: list[str], inputs: list[Path]) -> Path:
    """The cache folder of one build of crslab's own C: named by the compiler's identity, the flags
    and the content of every input."""
    digest = content_digest([cc.identity.encode(), " ".join(flags).encode()]
                            + [p.read_bytes() for p in inputs])
    return _subfolder(cache, f"{name}-{digest}")


def _board_objects(cc: Compiler, sanitize: bool, cache: Path, debug: bool = False) -> list[Path]:
    """The native board, framework stand-ins and kinematics objects, built once per content,
    flags and compiler."""
    flags = BOARD_FLAGS + (SANITIZE_FLAGS if sanitize else []) + (DEBUG_BOARD_FLAGS if debug else [])
    out_dir = _own_c_dir(cache, "board", cc, flags, BOARD_SOURCES + BOARD_HEADERS)
    return [_compiled(out_dir / f"{src.parent.name}_{src.stem}.o",
                      [*cc.argv, *flags, *firmware.csrc_debug_map(), *INCLUDES, "-c", str(src)],
                      f"crslab's board source {src.name}")
            for src in BOARD_SOURCES]


def trap_library(cc: Compiler, cache: Path) -> Path:
    """The run sandbox's SIGSYS handler (``csrc/sandbox/trap.c``, :mod:`crslab.sandbox.trap` loads
    it), built once per content and compiler, like the board."""
    out_dir = _own_c_dir(cache, "sandbox", cc, TRAP_FLAGS, [TRAP_SOURCE, *TRAP_HEADERS])
    return _compiled(out_dir / "trap.so",
                     [*cc.argv, *TRAP_FLAGS, "-I", str(BOARD), "-I", str(PLANT), "-I", str(PORT),
                      "-I", str(KIN), str(TRAP_SOURCE)],
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


COMPILED_FOLDER = "compiled"
"""The cache's folder of wasmtime's compiled firmware (:mod:`crslab.worker.wasm_runtime`)."""
READS_FILE = "reads.json"
"""A cached build's record of the files of the lab's folder its compiler read (their digests), and
of the names in the folder (``__has_include`` reads no file but sees a name)."""


def _sha(path: Path) -> str | None:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return None


def _variant(home: Path, lab: Path, image: str) -> Path | None:
    """The cached build in ``home`` (the folder of builds of one lab text) whose compiler read what
    the lab's folder holds now: the same names in the folder, the same bytes in each file it read;
    only what this user's build sealed counts. None when there is none."""
    files = allowed_files(lab.absolute().parent, [home.parent])  # the cache is no part of the lab
    listing = folder_listing(files)
    paths = {name: path for name, path, _ in files}
    for variant in sorted(home.iterdir()):
        try:
            if unsafe_reason(variant, follow=False) is not None:
                continue
        except OSError:
            continue
        record = read_sealed(variant / READS_FILE)
        if record is None or not is_sealed(variant / image):
            continue
        try:
            kept = json.loads(record)
        except ValueError:
            continue
        reads = kept.get("reads", {})
        if kept.get("listing") == listing and all(
                name in paths and _sha(paths[name]) == digest for name, digest in reads.items()):
            return variant
    return None


def _keep(home: Path, private: PrivateBuild, reads: list[str], outputs: dict[str, Path]) -> Path:
    """Put a finished build into the cache (``home``, a folder of its own named by what its compiler
    read: the names in the lab's folder and the bytes of each file it read, from the private copy),
    each output sealed; returns that folder."""
    record = {"listing": folder_listing(private.files),
              "reads": {name: _sha(private.source / name) for name in reads}}
    text = json.dumps(record, sort_keys=True)
    variant = _subfolder(home, f"v-{content_digest([text.encode()])}")
    for name, made in outputs.items():
        write_sealed(variant / name, made.read_bytes())
    write_sealed(variant / READS_FILE, text.encode())
    return variant


def _cached_or_built(home: Path, src: Path, text: bytes, image: str,
                     build: Callable[[PrivateBuild], tuple[dict[str, Path], list[str]]]) -> Path:
    """The folder of ``src``'s build in ``home``: the cached one whose compiler read what the lab's
    folder holds now (cheap: the folder's names and a digest of each file it read), else one
    ``build`` makes in a private build (:class:`crslab.lab.compile_process.PrivateBuild`, outside
    the cache: a build killed on its time leaves no text of the lab anywhere) and that is kept."""
    home = _subfolder(home.parent, home.name)
    found = _variant(home, src, image)
    if found is not None:
        return found
    with PrivateBuild(src, text, leave_out=[home.parent]) as private:
        outputs, reads = build(private)
        return _keep(home, private, reads, outputs)


def _build_wasm(src: Path, text: bytes, variables: list[LabVariable], calls: str, cache: Path,
                sandboxed: bool, memory: MemoryLayout) -> tuple[firmware.WasmImage, str]:
    """The WebAssembly firmware of ``src`` (its bytes ``text``; cached, named by the text and by
    what the compiler read of the lab's folder), its globals placed as ``memory`` says; returns
    (image, digest)."""
    _subfolder(cache, COMPILED_FOLDER)  # where the board's compilation is kept: said now if it cannot be
    try:
        libc = firmware.prepare_zig()
        objects = firmware.firmware_objects(cache, content_digest)
    except CacheError as exc:
        raise LabBuildError(str(exc)) from None
    except (RuntimeError, zig.ZigMissing, OSError) as exc:
        raise LabBuildError(f"the WebAssembly compiler cannot be used: {exc}") from None
    globals_ = [v.name for v in variables if not v.static]
    # the path as given, not the folder: the module names the lab as given (prefix maps), so a lab
    # given by the same relative path builds the same module in any folder (crslab serve's sessions)
    digest = content_digest([text, src.suffix.encode(), str(src).encode(),
                             " ".join([*firmware.C28X_TARGET, *firmware.LAB_FLAGS, *firmware.IR_FLAGS,
                                       *firmware.LINK_FLAGS]).encode(),
                             objects[0].parent.name.encode(), " ".join(globals_).encode()])

    def build(private: PrivateBuild) -> tuple[dict[str, Path], list[str]]:
        readable = [SHIM_INCLUDE, FIRMWARE, KIN, *BOARD_FOLDERS, objects[0].parent, libc.folder]
        sandbox = compiler_sandbox([], private.folder, readable, compiler=(), run_dirs=[zig.zig_dir()],
                                   cache_dirs=[zig.zig_cache()]) if sandboxed else None
        built, reads = firmware.build_module(private, globals_, objects, sandbox, calls, libc, memory)
        built.save(private.folder)
        return {"lab.wasm": built.path, "names.json": private.folder / "names.json"}, reads

    variant = _cached_or_built(cache / f"wasm-{digest}", src, text, "lab.wasm", build)
    image = firmware.WasmImage.load(variant)
    if image is None:
        raise LabBuildError(f"{src.name}: its build in {variant} cannot be read")
    return image, f"{digest}-{variant.name}"


def native_unit(lab: Path, calls: str, condition: str | None = None) -> str:
    """The translation unit of a native build: the lab file itself (by its absolute path), the
    ``--break-when`` condition when there is one (:func:`break_when_source`), then ``calls``, the
    framework's calls of the lab's functions (:mod:`crslab.lab.entry_points`).

    >>> native_unit(Path("/labs/lab1.c"), "")
    '#include "/labs/lab1.c"\\n'
    """
    if condition is not None:
        return break_when_source(lab, condition) + calls
    quoted = str(lab.absolute()).replace("\\", "\\\\").replace('"', '\\"')
    return f'#include "{quoted}"\n{calls}'


def _build_native(src: Path, text: bytes, flags: list[str], calls: str, break_when: str | None,
                  sanitize: bool, debug: bool, cache: Path,
                  sandboxed: bool) -> tuple[Path, str, Compiler, tuple[str, ...]]:
    """The native shared object of ``src`` (its bytes ``text``) linked with the board (cached, named
    like the WebAssembly build); returns (image, digest, cc, the C89 habits it was built with)."""
    cc = compiler()
    objects = _board_objects(cc, sanitize, cache, debug)
    flags = [*flags, *lab_flags(cc.family)]
    digest = content_digest([NATIVE_RECIPE, text, " ".join(flags).encode(), src.suffix.encode(),
                             calls.encode()]
                            + [o.parent.name.encode() for o in objects[:1]]  # it names the compiler
                            + ([break_when.encode()] if break_when is not None else [])
                            # a debugger finds the source by the path compiled into the build
                            + ([str(src.absolute()).encode()] if debug else []))
    given = firmware.given_prefix(src)
    # the copy's folder is named as the user's folder: __FILE__ and the debug information (a
    # debugger finds the source by it; absolute for crslab debug)
    shown = f"{src.absolute().parent}/" if debug else given

    def build(private: PrivateBuild) -> tuple[dict[str, Path], list[str]]:
        tmp, copy = private.folder, private.copy
        readable = [SHIM_INCLUDE, FIRMWARE, KIN, *BOARD_FOLDERS, objects[0].parent]
        sandbox = compiler_sandbox([], tmp, readable, compiler=cc.argv) if sandboxed else None
        obj = tmp / "lab.o"
        # the unit includes the lab's copy, then the framework's calls of its functions (their
        # lines are crslab-calls' and --break-when's): it is named as the lab, in a folder of its
        # own named as the lab's, so the debug information names the lab's file (the compilation
        # unit's name) where it is, as gdb shows it
        unit_dir = tmp / "unit"
        unit_dir.mkdir()
        compiled, what = unit_dir / copy.name, src.name
        compiled.write_text(native_unit(copy, calls, break_when))
        if break_when is not None:
            what = f"{src.name} with --break-when {break_when!r}"
        maps = [arg for folder in (copy.parent, unit_dir)
                for arg in (f"-fmacro-prefix-map={folder}/={shown}",
                            f"-fdebug-prefix-map={folder}={shown.rstrip('/') or '.'}")]
        try:
            messages = run_compiler([*cc.argv, *flags, *ERROR_LIMIT, *maps, "-iquote", str(copy.parent),
                                     *INCLUDES, "-MD", "-MF", str(tmp / "reads.d"), "-x", "c", "-c",
                                     str(compiled), "-o", str(obj)], what, sandbox, reaper=private.reaper)
        except LabBuildError as exc:
            exc.diagnostics = firmware.shown_diagnostics(exc.diagnostics, compiled, src, copy)
            raise
        habits = tmp / "habits.json"
        shown_messages = firmware.shown_diagnostics(messages, compiled, src, copy)
        habits.write_text(json.dumps(habit_warnings(shown_messages)))
        tmp_so = tmp / "lab.so"
        link_flags = [*os_support.SHARED_OBJECT_FLAGS, *(cc.sanitizer_link_flags() if sanitize else [])]
        try:
            run_compiler([*cc.argv, *link_flags, "-Wl,--no-undefined", "-o", str(tmp_so), str(obj),
                          *map(str, objects), *LINK_LIBS], f"{src.name} (link)", sandbox,
                         reaper=private.reaper)
        except LabForbidden:
            raise
        except LabBuildError as exc:
            if "undefined reference to `" in exc.diagnostics:
                text = exc.diagnostics.replace("undefined reference to `", "undefined symbol: ")
                raise firmware.link_failure(src, text) from None
            raise
        check_image(tmp_so, src.name)
        reads = private.read_from_folder(dependencies((tmp / "reads.d").read_text("utf-8", "replace")))
        return {"lab.so": tmp_so, "habits.json": habits}, reads

    variant = _cached_or_built(cache / f"lab-{digest}", src, text, "lab.so", build)
    try:
        habits = tuple(json.loads(read_sealed(variant / "habits.json") or b"[]"))
    except ValueError:
        habits = ()
    return variant / "lab.so", f"{digest}-{variant.name}", cc, habits


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
    try:  # how the framework calls lab() and printing(), as the file (and its own headers) define them
        own = header_texts(src, headers)
        calls = entry_calls("\n".join([text, *(t for _, t in own)]))
    except EntryPointError as exc:
        raise LabBuildError(f"{src.name} cannot run on the board: {exc}") from None
    generation = detect(text)
    variables = variables_of_files([*own, ("", text)])  # once: the layout, the watched ones, the unit
    memory = layout(variables, generation, src.stem)
    check_board_memory(memory, src)
    debug = debug or break_when is not None
    native = native or sanitize or debug
    cache = cache if cache is not None else _cache()
    cc: Compiler | None = None
    renamed: tuple[str, ...] = ()
    sized: tuple[str, ...] = ()
    trap: Path | None = None
    if native:
        flags = LAB_FLAGS + (SANITIZE_FLAGS if sanitize else []) + (DEBUG_LAB_FLAGS if debug else [])
        image, digest, cc, habits = _build_native(src, text_bytes, flags, calls, break_when, sanitize, debug,
                                                  cache, sandboxed)
        trap = trap_library(cc, cache)
    else:
        wasm, digest = _build_wasm(src, text_bytes, variables, calls, cache, sandboxed, memory)
        image, renamed, sized, habits = wasm.path, wasm.renamed, wasm.sized, wasm.habits
    return LabBuild(source=src, image=image, generation=generation, sanitized=sanitize, digest=digest,
                    native=native, watched=tuple(watched_of(variables)), compiler=cc, debug=debug,
                    break_when=break_when, variables=tuple(variables), memory=memory, renamed=renamed,
                    sized=sized, trap_library=trap, habits=habits)
