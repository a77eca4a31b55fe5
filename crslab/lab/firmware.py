"""Build a lab's WebAssembly firmware: the lab file, unmodified, linked with the framework's
stand-ins (``csrc/firmware``) and crslab's kinematics (``csrc/kin``, for labs that call it) into
one WebAssembly module, as the real lab is linked with the framework into the F28335's image.

zig's clang compiles it for wasm32 (:mod:`crslab.lab.zig`), with wasi-libc as its C library, in
the compile sandbox. The module's memory is fixed when it is linked (:data:`MEMORY_BYTES`, the
call stack first, so that a runaway recursion runs off its bottom and traps), and it imports only
the board's functions and the WASI calls the C library makes, which the board answers or refuses
(``csrc/sim/firmware_wasm.c``). Every global variable of the lab file that has a symbol is
exported by name, so the board finds its address (watched variables, the MATLAB tools).

A lab that calls a function nobody defines does not link: the message names the function. One
whose data does not fit the memory says how much it needs.

>>> undefined_functions("wasm-ld: error: /tmp/x/lab.o: undefined symbol: uname\\n")
['uname']
>>> memory_needed("wasm-ld: error: initial memory too small, 4196352 bytes needed")
4196352
"""

from __future__ import annotations

import os
import re
import subprocess
import tempfile
from pathlib import Path

from crslab import resources
from crslab.lab import zig
from crslab.lab.compile_process import COMPILE_TIMEOUT_S

TARGET = "wasm32-wasi"
STACK_BYTES = 64 * 1024
"""The firmware's C stack, at the bottom of its memory (the F28335's is 1 K words in M1; students'
local arrays need more on a host)."""
MEMORY_BYTES = 1024 * 1024
"""The firmware's whole memory, fixed: stack, data and heap (see docs/sandbox.md)."""
NATIVE_STACK_BYTES = 512 * 1024
"""The native stack wasmtime lets the firmware's calls use (recursion depth)."""

FIRMWARE = resources.path("csrc", "firmware")
KIN = resources.path("csrc", "kin")
SIM = resources.path("csrc", "sim")
SHIM_INCLUDE = resources.path("csrc", "board", "include")
INCLUDES = ["-I", str(SHIM_INCLUDE), "-I", str(FIRMWARE), "-I", str(KIN), "-I", str(SIM)]
COMPILE_FLAGS = ["-std=c11", "-O2", "-mexec-model=reactor", "-fno-common", "-g"]
LAB_FLAGS = [*COMPILE_FLAGS, "-w"]
FIRMWARE_FLAGS = [*COMPILE_FLAGS, "-Wall", "-Wextra", "-Werror"]
LINK_FLAGS = ["-mexec-model=reactor", f"-Wl,-z,stack-size={STACK_BYTES}", f"-Wl,--initial-memory={MEMORY_BYTES}",
              f"-Wl,--max-memory={MEMORY_BYTES}"]
"""zig's linker puts the stack first (tests/test_wasm_firmware.py checks it), then the data, then the heap."""
FIRMWARE_SOURCES = sorted(FIRMWARE.glob("*.c")) + sorted(KIN.glob("*.c"))
FIRMWARE_HEADERS = (sorted(FIRMWARE.glob("*.h")) + sorted(KIN.glob("*.h")) + sorted(SHIM_INCLUDE.glob("*.h"))
                    + [SIM / "sim.h", SIM / "framework_facts.h"])

_UNDEFINED = re.compile(r"undefined symbol: (\w+)")
_NOT_EXPORTED = re.compile(r"symbol exported via --export not found: (\w+)")
_CLASH = re.compile(r"(?:symbol type mismatch|duplicate symbol): (\w+)")
RENAMED_PREFIX = "crs_lab_"
"""A lab global whose name the C library also defines is compiled under this prefix (see
:func:`clashing_symbols`); the board finds it by the new name."""
_MEMORY = re.compile(r"initial memory too small, (\d+) bytes needed")


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


def prepare_zig() -> None:
    """zig's C library for wasm32, built once (with progress on stderr): see :func:`zig.prepare`."""
    zig.prepare(TARGET, LINK_FLAGS)


def firmware_objects(cache: Path, digest_of) -> list[Path]:  # noqa: ANN001 - build.content_digest
    """The stand-ins and the kinematics compiled for wasm32, once per content, flags and zig."""
    digest = digest_of([zig.zig_version().encode(), " ".join(FIRMWARE_FLAGS).encode()]
                       + [p.read_bytes() for p in FIRMWARE_SOURCES + FIRMWARE_HEADERS])
    out_dir = cache / f"firmware-{digest}"
    objects = [out_dir / f"{p.parent.name}_{p.stem}.o" for p in FIRMWARE_SOURCES]
    if all(o.exists() for o in objects):
        return objects
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=out_dir) as tmp:
        procs = []
        for src, obj in zip(FIRMWARE_SOURCES, objects):
            part = Path(tmp) / obj.name
            procs.append((subprocess.Popen([*zig.zig_cc(), f"--target={TARGET}", *FIRMWARE_FLAGS, *INCLUDES,
                                            "-c", str(src), "-o", str(part)],
                                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                           env=zig.zig_environment(Path(tmp) / "cache")), src, part, obj))
        failed = []
        for proc, src, part, obj in procs:
            _, err = proc.communicate(timeout=COMPILE_TIMEOUT_S)
            if proc.returncode != 0:
                failed.append(f"crslab's firmware source {src.name} does not compile for wasm32:\n{err}")
            else:
                part.replace(obj)
        if failed:
            raise RuntimeError("\n".join(failed))
    return objects


def exported_variables(names: list[str]) -> list[str]:
    """Linker flags exporting each of ``names`` (a data symbol's export holds its address)."""
    return [f"-Wl,--export={n}" for n in names if re.fullmatch(r"[A-Za-z_]\w*", n)]


def link_command(compiled: Path, objects: list[Path], out: Path, variables: list[str],
                 renamed: list[str] = ()) -> list[str]:  # type: ignore[assignment]
    """zig's command that compiles the lab file ``compiled`` (its globals ``renamed`` under
    :data:`RENAMED_PREFIX`) and links it into ``out``, exporting ``variables`` (as they are named
    in the image). A lab's ``main()`` is never called (the board runs the framework's loop), so it
    is compiled as an ordinary function: the course's ``void main(void)`` is fine on the C28x."""
    renames = [f"-D{n}={RENAMED_PREFIX}{n}" for n in renamed]
    return [*zig.zig_cc(), f"--target={TARGET}", *LAB_FLAGS, f"-Dmain={RENAMED_PREFIX}main", *renames, *INCLUDES,
            "-x", "c", str(compiled), "-x", "none", *map(str, objects), *LINK_FLAGS,
            *exported_variables(variables), "-o", str(out)]


def compile_environment(build_dir: Path) -> dict[str, str]:
    """zig's environment for one build: its own local cache inside the build folder."""
    env = zig.zig_environment(build_dir / "zig-cache")
    for key in ("TMPDIR", "TMP", "TEMP"):
        env[key] = str(build_dir)
    return env


