"""The C-level tests: each csrc/tests/test_*.c is built against every csrc/kin/*.c with
-Wall -Wextra -Werror, once plainly and once under AddressSanitizer and UBSan, and run; with gcc,
and with clang when it is installed (CI installs it). Tests of the emulated board
(``test_board_*.c``) also get the native board (every csrc/board/*.c but the WebAssembly port, with
csrc/plant and csrc/port), the framework's stand-ins (csrc/firmware) and shim headers: they drive
the framework's tick alone, with a stub plant and a test lab of their own as the board's native
firmware.

The core's and the board's sources are compiled once per compiler and mode into two static
libraries (in parallel, one compiler process per core) and every test links against them."""

import os
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from crslab.lab.build import wasm_port_only
from crslab.os_support import MATH_LIBS

ROOT = Path(__file__).resolve().parents[1]
CSRC = ROOT / "csrc"
KIN_SOURCES = sorted((CSRC / "kin").glob("*.c"))
SIM_SOURCES = (sorted(p for p in (CSRC / "board").glob("*.c") if not wasm_port_only(p))
               + sorted((CSRC / "plant").glob("*.c")) + sorted((CSRC / "port").glob("*.c"))
               + sorted((CSRC / "firmware").glob("*.c")))
C_TESTS = sorted((CSRC / "tests").glob("test_*.c"))
STRICT = ["-std=c11", "-Wall", "-Wextra", "-Werror", "-fno-math-errno", "-I", str(CSRC / "kin")]
SIM_INCLUDES = ["-I", str(CSRC / "board"), "-I", str(CSRC / "plant"), "-I", str(CSRC / "port"), "-I",
                str(CSRC / "firmware"), "-I", str(CSRC / "firmware" / "include")]
SANITIZE = ["-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer"]
COMPILERS = ["gcc", pytest.param("clang", marks=pytest.mark.requires("clang"))]


def flags(sanitize: bool) -> list[str]:
    """The compile flags of one mode (plain -O2, or -O1 -g under ASan and UBSan)."""
    return STRICT + SIM_INCLUDES + (["-O1", "-g"] + SANITIZE if sanitize else ["-O2"])


def archive(cc: str, sanitize: bool, sources: list[Path], out: Path) -> Path:
    """``sources`` compiled with ``cc`` (in parallel) into the static library ``out``."""
    objects = [out.parent / f"{out.stem}-{src.stem}.o" for src in sources]

    def compile_one(pair: tuple[Path, Path]) -> subprocess.CompletedProcess:
        src, obj = pair
        return subprocess.run([cc, *flags(sanitize), "-c", str(src), "-o", str(obj)],
                              capture_output=True, text=True)

    with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        for done in pool.map(compile_one, zip(sources, objects)):
            assert done.returncode == 0, done.stderr
    subprocess.run(["ar", "rcs", str(out), *map(str, objects)], check=True)
    return out


@pytest.fixture(scope="session")
def libraries(tmp_path_factory):
    """``libraries(cc, sanitize)``: the (board, core) static libraries, built on first use."""
    built: dict[tuple[str, bool], tuple[Path, Path]] = {}

    def get(cc: str, sanitize: bool) -> tuple[Path, Path]:
        if (cc, sanitize) not in built:
            folder = tmp_path_factory.mktemp(f"c-{cc}-{'asan' if sanitize else 'o2'}")
            built[(cc, sanitize)] = (archive(cc, sanitize, SIM_SOURCES, folder / "libsim.a"),
                                     archive(cc, sanitize, KIN_SOURCES, folder / "libkin.a"))
        return built[(cc, sanitize)]

    return get


@pytest.mark.parametrize("cc", COMPILERS)
@pytest.mark.parametrize("sanitize", [False, True], ids=["O2", "asan-ubsan"])
@pytest.mark.parametrize("source", C_TESTS, ids=[p.stem for p in C_TESTS])
def test_c_core(source, sanitize, cc, tmp_path, libraries):
    exe = tmp_path / source.stem
    libsim, libkin = libraries(cc, sanitize)
    libs = [str(libsim), str(libkin)] if source.stem.startswith("test_board_") else [str(libkin)]
    build = subprocess.run([cc, *flags(sanitize), str(source), *libs, "-o", str(exe), *MATH_LIBS],
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    run = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120,
                         env={"ASAN_OPTIONS": "detect_leaks=1", "UBSAN_OPTIONS": "print_stacktrace=1"})
    assert run.returncode == 0, run.stdout + run.stderr
    assert "all passed" in run.stdout
