"""Build a lab's WebAssembly firmware: the lab file, unmodified, linked with the framework's
stand-ins (``csrc/firmware``) and crslab's kinematics (``csrc/kin``, for labs that call it) into
one WebAssembly module, as the real lab is linked with the framework into the F28335's image.

The lab is compiled as the board compiles it: with the C28x's widths (``int`` 16 bits, ``long``
32, ``double`` 32) and the optimisation off, as every lab project of the course is built
(:data:`C28X_FLAGS`): zig's clang compiles it with its AVR front end, whose widths are the C28x's,
to LLVM IR, which :mod:`crslab.lab.c28x_ir` moves to wasm32 (its globals placed as the TI linker
places them, :mod:`crslab.lab.c28x_memory`), and zig compiles that for wasm32 and links it with
the framework's stand-ins (``csrc/firmware``, compiled for wasm32: :mod:`crslab.lab.zig`) and
wasi-libc, in the compile sandbox. The lab sees the C library through the headers of
``csrc/firmware/c28x``, which give it the C28x's widths too. The module's memory is fixed when it
is linked (:data:`MEMORY_BYTES`, the call stack first, so that a runaway recursion runs off its
bottom and traps), and it imports only
the board's functions and the WASI calls the C library makes, which the board answers or refuses
(``csrc/board/firmware_wasm.c``). Every global variable of the lab file that has a symbol is
exported by name, so the board finds its address (watched variables, the MATLAB tools).

A lab that calls a function nobody defines does not link: the message names the function. One
whose data does not fit the memory says how much it needs.

>>> undefined_functions("wasm-ld: error: /tmp/x/lab.o: undefined symbol: uname\\n")
['uname']
>>> memory_needed("wasm-ld: error: initial memory too small, 4196352 bytes needed")
4196352
"""

from __future__ import annotations

import importlib.resources
import json
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import TextIO

from crslab import resources
from crslab.cache import is_sealed, read_sealed, seal_file, subfolder
from crslab.lab import c28x_ir, zig
from crslab.lab.c28x_memory import MemoryLayout
from crslab.lab.c89_habits import habit_warnings, lab_flags
from crslab.lab.compile_process import (
    CompilerStopped,
    LabBuildError,
    LabForbidden,
    PrivateBuild,
    check_image,
    run_compiler,
    start_compile,
    visible_files,
)
from crslab.sandbox.compile_sandbox import CompilerSandbox

TARGET = "wasm32-wasi"
STACK_BYTES = 64 * 1024
"""The firmware's C stack, at the bottom of its memory (the F28335's is 1 K words in M1; students'
local arrays need more on a host)."""
MEMORY_BYTES = 1024 * 1024
"""The firmware's whole memory at most: stack, data, and the heap malloc grows (docs/sandbox.md)."""
NATIVE_STACK_BYTES = 512 * 1024
"""The native stack wasmtime lets the firmware's calls use (recursion depth)."""

FIRMWARE = resources.path("csrc", "firmware")
KIN = resources.path("csrc", "kin")
PORT = resources.path("csrc", "port")
SHIM_INCLUDE = resources.path("csrc", "firmware", "include")
INCLUDES = ["-I", str(SHIM_INCLUDE), "-I", str(FIRMWARE), "-I", str(KIN), "-I", str(PORT)]
"""The firmware's include folders: its stand-ins, the kinematics and the port it shares with the
board (nothing of the board's: tests/test_layout.py)."""
COMPILE_FLAGS = ["-std=c11", "-O2", "-mexec-model=reactor", "-fno-common", "-g"]
"""The framework's stand-ins' flags (crslab's emulation of the framework, not the board's code)."""
C28X_TARGET = ["--target=avr-freestanding", "-mmcu=atmega2560"]
"""The front end whose C widths are the C28x's: int 16 bits, long 32, long long 64, float and
double 32 (docs/framework.md section 9)."""
C28X_INCLUDE = resources.path("csrc", "firmware", "c28x")
"""The C library's headers as a lab compiled with the C28x's widths sees them."""
OPTIMISATION = ["-O0", "-ffp-contract=off"]
"""The course's CCS projects build every lab with the optimisation off (docs/framework.md section
12): each statement is executed as written, every global read from memory each time, so a loop
waiting for a global nothing changes spins, and nothing is assumed of signed overflow, aliasing or
uninitialised reads. ``-O0`` does the same; no multiply and add is fused (the F28335 has no fused
multiply-add)."""
C28X_FLAGS = ["-std=c11", *OPTIMISATION, "-ffreestanding", "-fno-common", "-g", "-fno-sanitize=all"]
"""How the lab and the kinematics are compiled to IR with the C28x's widths (no C library but the
headers of :data:`C28X_INCLUDE`; zig's own checks off: the lab's are :data:`LAB_CHECKS`)."""
LAB_CHECKS = "null"
LAB_FLAGS = [*C28X_FLAGS, *lab_flags("clang"), f"-fsanitize={LAB_CHECKS}",
             f"-fno-sanitize-recover={LAB_CHECKS}"]
"""The lab's flags: a NULL pointer dereferenced stops the run at its line (the handler is the
firmware's, csrc/firmware/firmware.c; on the F28335 address 0 is RAM and the board goes on; a native
build stops too). An integer division by zero goes on as on the C28x (:mod:`crslab.lab.c28x_arithmetic`).
The C89 habits the board's compiler builds build here too, as warnings
(:mod:`crslab.lab.c89_habits`); no other warning is shown."""
KIN_FLAGS = [*C28X_FLAGS, "-Wall", "-Wextra", "-Werror", "-Wno-unused-command-line-argument"]
"""crslab's kinematics, which crslab's own labs call, compiled with the lab's widths too (zig passes
``-c`` beside ``-S``, unused)."""
IR_FLAGS = ["-O0", "-fno-sanitize=all"]
"""How the lab's IR, moved to wasm32 (:mod:`crslab.lab.c28x_ir`), is compiled: as it is."""
FIRMWARE_FLAGS = [*COMPILE_FLAGS, "-Wall", "-Wextra", "-Werror"]
LINK_FLAGS = ["-mexec-model=reactor", f"-Wl,-z,stack-size={STACK_BYTES}", f"-Wl,--max-memory={MEMORY_BYTES}"]
"""zig's linker puts the stack first (tests/test_wasm_firmware.py checks it), then the data, then the heap."""
FIRMWARE_SOURCES = sorted(FIRMWARE.glob("*.c")) + sorted(PORT.glob("*.c"))
"""The stand-ins and the generations' rows (the board compiles the same rows), compiled for wasm32."""
KIN_SOURCES = sorted(KIN.glob("*.c"))
"""The kinematics, compiled with the lab's widths (:data:`KIN_FLAGS`)."""
FIRMWARE_HEADERS = (sorted(FIRMWARE.glob("*.h")) + sorted(KIN.glob("*.h")) + sorted(SHIM_INCLUDE.glob("*.h"))
                    + sorted(PORT.glob("*.h")) + sorted(C28X_INCLUDE.rglob("*.h")))
IR_MOVER_MODULES = ("c28x_ir.py", "c28x_arithmetic.py", "c28x_memory.py", "variables.py")
"""The modules that move the lab's IR to wasm32 and place its globals (:mod:`crslab.lab.c28x_ir`
and every module of crslab.lab it imports, directly or not): a change to any of them changes what
a build makes."""


def ir_mover_text() -> bytes:
    """The text of :data:`IR_MOVER_MODULES`, part of every build's name (read as resources: crslab
    may be imported from a zip)."""
    folder = importlib.resources.files("crslab.lab")
    return b"".join(folder.joinpath(name).read_bytes() for name in IR_MOVER_MODULES)

FRAMEWORK_VARIABLES = ("matlabLock", *(f"SIMU_Var{i}_fromSIMU_16bit" for i in range(1, 8)))
"""The framework's globals in the firmware that the board's memory map holds (firmware.c)."""

_UNDEFINED = re.compile(r"undefined symbol: (\w+)")
_NOT_EXPORTED = re.compile(r"symbol exported via --export not found: (\w+)")
_CLASH = re.compile(r"(?:symbol type mismatch|duplicate symbol): (\w+)")
RENAMED_PREFIX = c28x_ir.RENAMED_PREFIX
"""A lab global whose name the C library also defines is compiled under this prefix (see
:func:`clashing_symbols`); the board finds it by the new name."""
_MEMORY = re.compile(r"(?:initial|maximum) memory too small, (\d+) bytes needed")


def undefined_functions(diagnostics: str) -> list[str]:
    """The symbols the linker could not find, in order, once each."""
    out: list[str] = []
    for name in _UNDEFINED.findall(diagnostics):
        if name not in out:
            out.append(name)
    return out


def not_exported(diagnostics: str) -> list[str]:
    """Variables the build was told to export that the lab does not define after all.

    >>> not_exported("wasm-ld: error: symbol exported via --export not found: x_in")
    ['x_in']
    """
    return _NOT_EXPORTED.findall(diagnostics)


def clashing_symbols(diagnostics: str) -> list[str]:
    """Globals of the lab that the WebAssembly C library also defines (course labs name variables
    ``index``, ``time``, ``step``...): on the board, and in a native build (``-Bsymbolic``), the
    lab's own win; here the lab file is compiled again with each renamed (``-Dindex=crs_lab_index``),
    which changes nothing the lab computes.

    >>> clashing_symbols("wasm-ld: error: symbol type mismatch: index\\n>>> defined as ...")
    ['index']
    """
    return list(dict.fromkeys(_CLASH.findall(diagnostics)))


def memory_needed(diagnostics: str) -> int | None:
    """The memory (bytes) the linker said the firmware needs, when it does not fit."""
    m = _MEMORY.search(diagnostics)
    return int(m.group(1)) if m else None


def prepare_zig(stream: TextIO | None = None) -> zig.LibC:
    """zig's C library for wasm32, built once per installation (with progress on ``stream``, default
    stderr): see :func:`zig.prepare`."""
    return zig.prepare(TARGET, LINK_FLAGS, stream)


def is_zig_prepared() -> bool:
    """Whether the firmware's C library is built already (a first build then takes seconds)."""
    return zig.is_prepared(TARGET, LINK_FLAGS)


DEBUG_INFO_CSRC = "/crslab/csrc"
"""How debug information names crslab's C folder, the same from every checkout: a build of crslab's
own C is shared by content through the cache, so a path of its own would name whichever checkout
built it first. ``crslab debug`` tells gdb where the folder is (``set substitute-path``)."""


def csrc_debug_map(compiler_option: list[str] | None = None) -> list[str]:
    """The flags that name crslab's C folder :data:`DEBUG_INFO_CSRC` in debug information (zig
    passes the map on only through ``-Xclang``: ``compiler_option``). Not part of a build's cache
    key: what they produce is the same from every checkout.

    >>> csrc_debug_map()[0].endswith("=/crslab/csrc")
    True
    """
    return [*(compiler_option or []), f"-fdebug-prefix-map={resources.path('csrc')}={DEBUG_INFO_CSRC}"]


def firmware_objects(cache: Path, digest_of) -> list[Path]:  # noqa: ANN001 - build.content_digest
    """The stand-ins compiled for wasm32 and the kinematics compiled with the lab's widths and moved to
    wasm32 (:mod:`crslab.lab.c28x_ir`), once per content, flags and zig: each object sealed
    (:func:`crslab.cache.seal_file`) and linked into a lab only while its seal holds (a folder or file
    of the cache that cannot be used raises :class:`crslab.cache.CacheError`)."""
    digest = digest_of([zig.zig_version().encode(), " ".join(FIRMWARE_FLAGS + KIN_FLAGS + IR_FLAGS).encode()]
                       + [p.read_bytes() for p in [*FIRMWARE_SOURCES, *KIN_SOURCES, *FIRMWARE_HEADERS]]
                       + [ir_mover_text()])
    out_dir = subfolder(cache, f"firmware-{digest}")
    sources = [*FIRMWARE_SOURCES, *KIN_SOURCES]
    objects = [out_dir / f"{p.parent.name}_{p.stem}.o" for p in sources]
    if all(is_sealed(o) for o in objects):
        return objects
    with tempfile.TemporaryDirectory(dir=out_dir) as tmp:
        work = Path(tmp)
        env = zig.zig_environment(work / "cache")
        mapped = csrc_debug_map(["-Xclang"])  # debug information names no checkout

        def compile_all(jobs: list[tuple[list[str], Path, Path]], what: str) -> None:
            procs = []
            try:
                for argv, src, part in jobs:
                    procs.append((start_compile([*argv, "-o", str(part)], cwd=work, env=env), src))
                failed = [f"crslab's firmware source {src.name} does not compile {what}:\n{r.stderr}"
                          for proc, src in procs if (r := proc.wait()).returncode != 0]
            finally:
                for proc, _ in procs:
                    proc.kill()
            if failed:
                raise RuntimeError("\n".join(failed))

        wasm = [*zig.zig_cc(), f"--target={TARGET}"]
        ir = {src: work / f"{src.stem}.avr.ll" for src in KIN_SOURCES}
        compile_all([([*wasm, *FIRMWARE_FLAGS, *mapped, *INCLUDES, "-c", str(src)], src, work / obj.name)
                     for src, obj in zip(FIRMWARE_SOURCES, objects)]
                    + [([*zig.zig_cc(), *C28X_TARGET, *KIN_FLAGS, *mapped, "-isystem", str(C28X_INCLUDE),
                         "-I", str(KIN), "-S", "-emit-llvm", str(src)], src, ir[src]) for src in KIN_SOURCES],
                    "for wasm32 (or with the C28x's widths)")
        for src in KIN_SOURCES:
            moved, _ = c28x_ir.to_wasm32(ir[src].read_text())
            ir[src].with_suffix(".wasm32.ll").write_text(moved)
        compile_all([([*wasm, *IR_FLAGS, "-c", str(ir[src].with_suffix(".wasm32.ll"))], src,
                      work / f"{src.parent.name}_{src.stem}.o") for src in KIN_SOURCES], "moved to wasm32")
        for obj in objects:
            seal_file(work / obj.name, obj)
    return objects


def exported_variables(names: list[str]) -> list[str]:
    """Linker flags exporting each of ``names`` (a data symbol's export holds its address)."""
    return [f"-Wl,--export={n}" for n in names if re.fullmatch(r"[A-Za-z_]\w*", n)]


GLOBALS_UNIT = "crslab-globals"
"""The name the size table's lines go by in the compiler's messages (:func:`unit_text`)."""
SIZES_SYMBOL = "crs_fw_global_sizes"
"""The table of the lab's globals' sizes in bytes, exported with the image."""
MAX_ROUNDS = 12
"""Compiles of one build: each round drops a name the lab does not define after all, or renames
one the C library also defines."""


def unit_text(lab: Path, sized: list[str], calls: str = "") -> str:
    """The translation unit the firmware is compiled from: the lab file itself, then the size in
    bytes of each of its globals ``sized`` as the compiler laid it out (32-bit numbers, the board reads
    them so, whatever the lab's widths), so the board never reads or
    writes a variable past its end (the source's reading of a size may be wrong), then ``calls``,
    the framework's calls of the lab's functions (:mod:`crslab.lab.entry_points`).

    >>> print(unit_text(Path("/labs/lab1.c"), ["mycount", "theta1array"]))
    #include "/labs/lab1.c"
    #line 1 "crslab-globals"
    const unsigned long crs_fw_global_sizes[] = {0
    , sizeof(mycount)
    , sizeof(theta1array)
    };
    <BLANKLINE>
    """
    lines = [f'#include "{lab.absolute()}"', f'#line 1 "{GLOBALS_UNIT}"',
             f"const unsigned long {SIZES_SYMBOL}[] = {{0"]
    lines += [f", sizeof({name})" for name in sized]
    return "\n".join([*lines, "};", ""]) + calls


def failed_sizes(diagnostics: str, sized: list[str]) -> list[str]:
    """The names whose line of the size table did not compile (a global the source's reading found
    that the compiler does not see: in a branch of an ``#if``, a macro).

    >>> failed_sizes("crslab-globals:3:10: error: use of undeclared identifier 'x_in'", ["a", "x_in"])
    ['x_in']
    """
    lines = {int(n) for n in re.findall(rf"{re.escape(GLOBALS_UNIT)}:(\d+):\d+: error", diagnostics)}
    return [name for i, name in enumerate(sized) if i + 2 in lines]


def prefix_maps(folders: list[Path], given: str) -> list[str]:
    """clang's flags that name ``folders`` (the lab's, and the build's copy of it) as the lab's
    folder was given (``given``: empty, or the folder as typed with its slash) in ``__FILE__`` and
    in the debug information wasmtime's backtraces quote (zig passes the debug map on only through
    ``-Xclang``; the compilation's own folder is ``.``).

    >>> prefix_maps([Path("/home/s/labs")], "")[:3]
    ['-fmacro-prefix-map=/home/s/labs/=', '-Xclang', '-fdebug-prefix-map=/home/s/labs=.']
    """
    flags = []
    for folder in dict.fromkeys(folders):
        # the debug map takes the folder itself (its table of folders names it without a slash)
        flags += [f"-fmacro-prefix-map={folder}/={given}", "-Xclang",
                  f"-fdebug-prefix-map={folder}={given.rstrip('/') or '.'}"]
    return [*flags, "-Xclang", "-fdebug-compilation-dir=."]


def given_prefix(lab: Path) -> str:
    """The lab's folder as the user gave it, as a prefix of its files' names (empty, or with its slash).

    >>> given_prefix(Path("lab.c")), given_prefix(Path("labs/me/lab.c"))
    ('', 'labs/me/')
    """
    return "" if str(lab.parent) == "." else f"{lab.parent}/"


def ir_command(unit: Path, lab: Path, copy: Path, renamed: list[str]) -> list[str]:
    """zig's command that compiles ``unit`` (including ``copy``, the private copy of the lab file
    ``lab``, and its size table; the lab's globals ``renamed`` under :data:`RENAMED_PREFIX`) with the
    C28x's widths (:data:`LAB_FLAGS`) to LLVM IR, ``lab.avr.ll`` beside it, and writes the files it
    read on its stderr (``-H``, :func:`included_files`: the build is named by them; zig's ``-MD``
    writes no IR beside its dependency file). The compiler sees
    the build's folder (the copy of the lab's folder in it), crslab's headers and zig's own,
    nothing else. A lab's ``main()`` is never called (the board runs the framework's loop), so it is
    compiled as an ordinary function: the course's ``void main(void)`` is fine on the C28x.
    ``__FILE__`` names the lab as it was given."""
    renames = [f"-D{n}={RENAMED_PREFIX}{n}" for n in renamed]
    folders = [unit.parent, SHIM_INCLUDE, FIRMWARE, KIN, PORT, zig.zig_dir() / "lib"]
    overlay = visible_files(unit.parent, [f.absolute() for f in folders])
    return [*zig.zig_cc(), *C28X_TARGET, *LAB_FLAGS, f"-Dmain={RENAMED_PREFIX}main", *renames,
            *prefix_maps([copy.parent], given_prefix(lab)),
            "-ivfsoverlay", str(overlay), "-H", "-iquote", str(copy.parent), "-isystem", str(C28X_INCLUDE),
            *INCLUDES,
            "-S", "-emit-llvm", "-x", "c", str(unit), "-o", str(unit.parent / "lab.avr.ll")]


_INCLUDED = re.compile(r"^\.+ (.+)\n?", re.MULTILINE)


def included_files(messages: str) -> tuple[list[str], str]:
    """The files a compile with ``-H`` included (each line: dots, one per level, and the path), and
    its other messages.

    >>> included_files(". /b/lab.c\\n.. /b/gains.h\\nlab.c:3:1: warning: w\\n")
    (['/b/lab.c', '/b/gains.h'], 'lab.c:3:1: warning: w\\n')
    """
    return _INCLUDED.findall(messages), _INCLUDED.sub("", messages)


def link_command(ir: Path, objects: list[Path], out: Path, exported: list[str], libc: zig.LibC) -> list[str]:
    """zig's command that compiles the lab's IR moved to wasm32 (``ir``) and links it with the
    firmware's ``objects`` and zig's C library ``libc`` (built once, :func:`prepare_zig`: linked as
    objects, so zig never builds it) into ``out``, exporting ``exported`` (as they are named in the
    image)."""
    return [*zig.zig_cc(), f"--target={TARGET}", *IR_FLAGS, "-nostdlib", str(ir), *map(str, objects),
            *map(str, libc.link), *LINK_FLAGS, *exported_variables([*exported, SIZES_SYMBOL]), "-o", str(out)]


@dataclass(frozen=True)
class WasmImage:
    """A built firmware module and what the board needs to know of its names."""

    path: Path
    renamed: tuple[str, ...]
    """The lab's globals compiled under another name (:func:`clashing_symbols`)."""
    sized: tuple[str, ...]
    """The lab's globals in the module's size table, in its order."""
    habits: tuple[str, ...] = ()
    """The C89 habits the lab was built with, one line each (:func:`crslab.lab.c89_habits.habit_warnings`)."""

    def save(self, folder: Path) -> None:
        (folder / "names.json").write_text(json.dumps({"renamed": self.renamed, "sized": self.sized,
                                                       "habits": self.habits}))

    @staticmethod
    def load(folder: Path) -> WasmImage | None:
        """The image cached in ``folder`` (both files as this user's build sealed them), or None."""
        try:
            names = json.loads(read_sealed(folder / "names.json") or b"")
        except ValueError:
            return None
        image = folder / "lab.wasm"
        if not is_sealed(image):
            return None
        return WasmImage(image, tuple(names["renamed"]), tuple(names["sized"]),
                         tuple(names.get("habits", ())))


def build_module(private: PrivateBuild, globals_: list[str], objects: list[Path],
                 sandbox: CompilerSandbox | None, calls: str = "", libc: zig.LibC | None = None,
                 memory: MemoryLayout | None = None) -> tuple[WasmImage, list[str]]:
    """Compile and link the lab of ``private`` (its private copy) into ``lab.wasm`` in the build's
    folder, exporting and sizing ``globals_`` (its globals as the source reads them) and the
    framework's variables, with ``calls`` (the framework's calls of its functions,
    :func:`crslab.lab.entry_points.entry_calls`), its globals placed as ``memory`` (the TI linker's
    layout of them) says; returns the image and the files of the lab's folder the compiler read
    (names from the folder). Raises LabBuildError (one line naming the problem)."""
    lab, build_dir, included = private.lab, private.folder, private.copy
    libc = libc if libc is not None else prepare_zig()
    sized = list(globals_)
    exported = sorted(set(globals_) | set(FRAMEWORK_VARIABLES))
    renamed: list[str] = []
    unit = build_dir / "firmware.c"
    ir = build_dir / "lab.wasm32.ll"
    out = build_dir / "lab.wasm"
    env = compile_environment(build_dir)
    for _ in range(MAX_ROUNDS):
        unit.write_text(unit_text(included, sized, calls))
        names = [RENAMED_PREFIX + n if n in renamed else n for n in exported]
        try:
            # run from the build's folder: the compiler's own folder names no folder of the user's
            command = ir_command(unit, lab, included, renamed)
            reads, messages = included_files(run_compiler(command, lab.name, sandbox, env=env, cwd=build_dir,
                                                          reaper=private.reaper))
            placement = c28x_ir.placement(memory, renamed) if memory is not None else None
            moved, _ = c28x_ir.to_wasm32((build_dir / "lab.avr.ll").read_text("utf-8", "replace"), placement)
            ir.write_text(moved)
            run_compiler(link_command(ir, objects, out, names, libc), lab.name, sandbox, env=env,
                         cwd=build_dir, reaper=private.reaper)
            break
        except (LabForbidden, CompilerStopped) as exc:
            exc.diagnostics = shown_diagnostics(included_files(exc.diagnostics)[1], unit, lab, included)
            raise
        except c28x_ir.IRError as exc:
            raise LabBuildError(f"{lab.name} cannot be built with the C28x's widths: {exc}") from None
        except LabBuildError as exc:
            text = shown_diagnostics(included_files(exc.diagnostics)[1], unit, lab, included)
            absent = {n.removeprefix(RENAMED_PREFIX) for n in not_exported(text)}
            absent |= set(failed_sizes(text, sized))
            clashes = [n for n in clashing_symbols(text) if n not in renamed]
            if absent & set(exported) or clashes:
                exported = [n for n in exported if n not in absent]
                sized = [n for n in sized if n not in absent]
                renamed += clashes
                continue
            raise link_failure(lab, text) from None
    else:
        raise LabBuildError(f"{lab.name} does not link: too many of its names clash with the C library's")
    check_image(out, lab.name)
    habits = habit_warnings(shown_diagnostics(messages, unit, lab, included))
    return WasmImage(out, tuple(renamed), tuple(sized), tuple(habits)), private.read_from_folder(reads)


def shown_diagnostics(diagnostics: str, unit: Path, lab: Path, copy: Path | None = None) -> str:
    """The compiler's messages as the user should read them: about the lab and its folder's files
    as they named them (not the build's ``copy`` of them), without the line that says the lab was
    included by crslab's unit.

    >>> shown_diagnostics("In file included from /b/firmware.c:1:\\n/b/submission/lab.c:3:1: error: e",
    ...                   Path("/b/firmware.c"), Path("x/lab.c"), Path("/b/submission/lab.c"))
    'x/lab.c:3:1: error: e'
    """
    lines = [line for line in diagnostics.splitlines(keepends=True)
             if not line.startswith(f"In file included from {unit}:")]
    text = "".join(lines)
    if copy is not None:
        text = text.replace(str(copy), str(lab)).replace(f"{copy.parent}/", given_prefix(lab))
    return text.replace(str(lab.absolute()), str(lab))


def link_failure(lab: Path, diagnostics: str) -> LabBuildError:
    """The one-line error of a failed build: a function nobody defines, memory the board lacks."""
    missing = undefined_functions(diagnostics)
    if missing:
        shown = ", ".join(f"{m}()" for m in missing[:4]) + (", ..." if len(missing) > 4 else "")
        return LabBuildError(f"{lab.name} does not compile: it calls {shown}, which neither the file nor the "
                             "board's framework defines", diagnostics)
    needed = memory_needed(diagnostics)
    if needed is not None:
        return LabBuildError(f"{lab.name} does not fit the board: it needs {needed / 1024:,.0f} KB of "
                             f"memory, crslab's board gives a lab {MEMORY_BYTES // 1024:,} KB (stack, data "
                             "and heap)", diagnostics)
    return LabBuildError(f"{lab.name} does not compile", diagnostics)


def compile_environment(build_dir: Path) -> dict[str, str]:
    """zig's environment for one build: its own local cache inside the build folder."""
    env = zig.zig_environment(build_dir / "zig-cache")
    for key in ("TMPDIR", "TMP", "TEMP"):
        env[key] = str(build_dir)
    return env


