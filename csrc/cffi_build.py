"""cffi (API mode, out of line) build of the crslab C core into ``crslab._core``.

The Python-visible declarations are read from the public headers listed in ``HEADERS``
(crslab/cheaders.py drops preprocessor lines and ``static const`` initialisers), so every fact
and every prototype is written once, in its header. Every ``*.c`` file under ``csrc/kin`` is
compiled in, and so are the board (``csrc/board``) with the WebAssembly firmware's port
(``firmware_wasm.c``; the native port is linked with a lab instead, crslab/lab/build.py), the
plant's C (``csrc/plant``), what the board shares with the firmware (``csrc/port``) and the
page's rows packed from the shared block (``csrc/page``: a run host's): the worker runs a lab's
WebAssembly firmware on this board. The course framework's numbers
(``csrc/port/framework_facts.h``, declarations only) and its generations' rows (``generations.h``,
the rows in ``generations.c``) come along so that Python reads them from the same C the emulated
board is built with.
"""

from __future__ import annotations

import importlib.util
import platform
import sys
from pathlib import Path

from cffi import FFI

HERE = Path(__file__).resolve().parent
KIN = HERE / "kin"
BOARD = HERE / "board"
PLANT = HERE / "plant"
PORT = HERE / "port"
PAGE = HERE / "page"
# The plant's headers, whose types the board's struct holds (board.h includes them; cffi reads no
# #include, so they come before it).
PLANT_TYPES = [PLANT / "drive.h", PLANT / "friction.h", PLANT / "hand.h", PLANT / "plant_faults.h",
               PLANT / "push.h", PLANT / "world_facts.h", PLANT / "world.h"]
# vector_math.h is internal (attributes, no API); every other header is the Python-visible API.
HEADERS = sorted(h for h in KIN.glob("*.h") if h.name != "vector_math.h") + [
    PORT / "framework_facts.h", PORT / "generations.h", PORT / "firmware_board.h", *PLANT_TYPES,
    BOARD / "board.h", BOARD / "board_config.h", BOARD / "firmware_wasm.h", PAGE / "page_rows.h"]
NATIVE_ONLY = {"firmware_native.c", "debug.c"}
"""Board sources linked only with a native lab (crslab/lab/build.py), never into the core: the
native port and what a debugger reads (a second ``crs_tick`` here would be the one gdb finds)."""
SOURCES = (sorted(KIN.glob("*.c")) + sorted(p for p in BOARD.glob("*.c") if p.name not in NATIVE_ONLY)
           + sorted(PLANT.glob("*.c")) + sorted(PORT.glob("*.c")) + sorted(PAGE.glob("*.c")))
INCLUDE_DIRS = (KIN, BOARD, PLANT, PORT, PAGE)
"""Where the core's sources find their headers."""
C_FLAGS = ["-std=c11", "-O3", "-Wall", "-Wextra", "-Werror", "-fno-math-errno", "-fno-trapping-math",
           "-fno-semantic-interposition", "-flto"]
LINK_FLAGS = ["-flto=auto", "-Wall", "-Wextra", "-Werror"]
"""Link-time optimization: the tick's calls from one source into another (tick.c into the
framework, the drive, friction, the hand, the serial lines and host ports: some twenty a tick)
are inlined or made direct, as calls within one file are; ``-fno-semantic-interposition`` lets
the compiler do so for the functions the core exports. The code link-time optimization writes is
checked with the same warnings. No floating-point option changes: the same operations, the same
bits (the transcripts are byte-identical); about 0.2-0.3 us less of a tick's 6.3 us of worker CPU
(tools/bench.py sim). The link (``-flto=auto``) runs its jobs in parallel, as many as the machine
has (with a bare ``-flto`` gcc runs them one after another and says so on every build)."""
# glibc's vector math (libmvec) backs the vectorized batch loops on x86-64 Linux.
# pthread: the WebAssembly port's watchdog thread (interrupts per store)
LIBRARIES = (["m", "mvec"] if platform.machine() == "x86_64" and sys.platform == "linux" else ["m"]) + ["dl",
                                                                                                      "pthread"]


def _load_cheaders():
    """crslab/cheaders.py by path: the build must not import the package it builds."""
    spec = importlib.util.spec_from_file_location("crslab_cheaders", HERE.parent / "crslab" / "cheaders.py")
    module = importlib.util.module_from_spec(spec)
    assert spec.loader is not None
    spec.loader.exec_module(module)
    return module


cdef_from_header = _load_cheaders().cdef_from_header

ffibuilder = FFI()
ffibuilder.cdef("\n".join(cdef_from_header(h.read_text()) for h in HEADERS))
ffibuilder.set_source(
    "crslab._core",
    "\n".join(f'#include "{h.name}"' for h in HEADERS),
    sources=[str(s.relative_to(HERE.parent)) for s in SOURCES],
    include_dirs=[str(d.relative_to(HERE.parent)) for d in INCLUDE_DIRS],
    extra_compile_args=C_FLAGS,
    libraries=LIBRARIES,
    extra_link_args=LINK_FLAGS,
)

if __name__ == "__main__":
    ffibuilder.compile(verbose=True)
