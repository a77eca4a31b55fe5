"""The C-level tests: each csrc/tests/test_*.c is built against every csrc/kin/*.c with
-Wall -Wextra -Werror, once plainly and once under AddressSanitizer and UBSan, and run; with gcc,
and with clang when it is installed (CI installs it). Tests of the emulated board
(``test_sim_*.c``) also get every csrc/sim/*.c and the framework's shim headers: they drive the
framework's tick alone, with a stub plant and a test lab of their own."""

import subprocess
from pathlib import Path

import pytest

from crslab.os_support import MATH_LIBS

ROOT = Path(__file__).resolve().parents[1]
CSRC = ROOT / "csrc"
KIN_SOURCES = sorted(str(p) for p in (CSRC / "kin").glob("*.c"))
SIM_SOURCES = sorted(str(p) for p in (CSRC / "sim").glob("*.c"))
C_TESTS = sorted((CSRC / "tests").glob("test_*.c"))
STRICT = ["-std=c11", "-Wall", "-Wextra", "-Werror", "-fno-math-errno", "-I", str(CSRC / "kin")]
SIM_INCLUDES = ["-I", str(CSRC / "sim"), "-I", str(CSRC / "board" / "include")]
SANITIZE = ["-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer"]
COMPILERS = ["gcc", pytest.param("clang", marks=pytest.mark.requires("clang"))]


@pytest.mark.parametrize("cc", COMPILERS)
@pytest.mark.parametrize("sanitize", [False, True], ids=["O2", "asan-ubsan"])
@pytest.mark.parametrize("source", C_TESTS, ids=[p.stem for p in C_TESTS])
def test_c_core(source, sanitize, cc, tmp_path):
    exe = tmp_path / source.stem
    flags = STRICT + (["-O1", "-g"] + SANITIZE if sanitize else ["-O2"])
    sources = KIN_SOURCES
    if source.stem.startswith("test_sim_"):
        flags += SIM_INCLUDES
        sources = KIN_SOURCES + SIM_SOURCES
    build = subprocess.run([cc, *flags, str(source), *sources, "-o", str(exe), *MATH_LIBS],
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    run = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120,
                         env={"ASAN_OPTIONS": "detect_leaks=1", "UBSAN_OPTIONS": "print_stacktrace=1"})
    assert run.returncode == 0, run.stdout + run.stderr
    assert "all passed" in run.stdout
