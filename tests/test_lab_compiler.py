"""Any C compiler the user has: CC chooses it (default cc, then gcc, then clang), a lab builds and
runs with clang as with gcc, the build cache keeps their builds apart, and a missing compiler is
one line saying how to install one."""

import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from crslab.lab.compiler import INSTALL_HINT, CompilerMissing, find_compiler

ROOT = Path(__file__).resolve().parents[1]
LABS = Path(__file__).parent / "labs"


def crslab(*args, env=None, cwd=None, timeout=120):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, env=env, cwd=cwd)


def bin_with(tmp_path, *names):
    """A folder holding only links to the named compilers: a PATH with exactly these."""
    folder = tmp_path / "bin"
    folder.mkdir()
    for name in names:
        (folder / name).symlink_to(shutil.which(name))
    return str(folder)


@pytest.mark.requires("clang")
def test_default_order_is_cc_then_gcc_then_clang(tmp_path):
    path = bin_with(tmp_path, "gcc", "clang")
    c = find_compiler({"PATH": path})
    assert c.command == ("gcc",) and c.family == "gcc"
    os.unlink(Path(path) / "gcc")
    c = find_compiler({"PATH": path})
    assert c.command == ("clang",) and c.family == "clang"
    dumped = subprocess.run(["clang", "-dumpversion"], capture_output=True, text=True).stdout.strip()
    assert c.version == dumped
    (Path(path) / "cc").symlink_to(shutil.which("gcc"))
    assert find_compiler({"PATH": path}).command == ("cc",)
    # CC wins over the default order
    assert find_compiler({"PATH": path, "CC": "clang"}).family == "clang"


def test_a_missing_compiler_says_how_to_install_one(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(CompilerMissing) as exc:
        find_compiler({"PATH": str(empty)})
    assert str(exc.value) == f"no C compiler on PATH (tried cc, gcc, clang); {INSTALL_HINT}"
    # the WebAssembly build needs no host compiler (zig comes with crslab); a native one does
    no_compiler = {**os.environ, "PATH": str(empty), "CC": ""}
    r = crslab("sim", "--fast", "--duration", "5", "--quiet", env=no_compiler)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("0.00 -24.06 13.75\n")
    r = crslab("sim", "--native", "--fast", "--duration", "1", env=no_compiler)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.strip() == f"crslab sim: no C compiler on PATH (tried cc, gcc, clang); {INSTALL_HINT}"
    r = crslab("sim", "--native", "--fast", "--duration", "1", env={**os.environ, "CC": "no-such-cc -O1"})
    assert r.returncode == 2
    assert r.stderr.strip() == (f"crslab sim: CC=no-such-cc -O1: no-such-cc was not found on PATH; "
                                f"{INSTALL_HINT}")


@pytest.mark.requires("clang")
def test_a_lab_built_with_clang_prints_what_the_gcc_build_prints(tmp_path):
    """CC=clang builds the board and the lab with clang (its mark is in the object's .comment),
    in a cache entry of its own, and the transcript is gcc's, byte for byte."""
    transcripts, comments, digests = {}, {}, {}
    for cc in ("gcc", "clang"):
        t = tmp_path / f"{cc}.txt"
        r = crslab("sim", "--fast", "--duration", "8", "--lab", LABS / "gen_a_libc_names.c", "--scenario",
                   "tour", "--transcript", t, env={**os.environ, "CC": cc})
        assert r.returncode == 0, r.stderr
        transcripts[cc] = t.read_bytes()
        lab = str(LABS / "gen_a_libc_names.c")
        probe = (f"from crslab.lab.build import build_lab; b = build_lab({lab!r}, native=True); "
                 "print(b.digest, b.shared_object)")
        digests[cc], so = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                                         env={**os.environ, "CC": cc}, check=True).stdout.split()
        comments[cc] = subprocess.run(["readelf", "-p", ".comment", so], capture_output=True,
                                      text=True).stdout
    assert transcripts["gcc"] == transcripts["clang"] and transcripts["gcc"].count(b"\n\r") >= 4
    assert digests["gcc"] != digests["clang"]  # the compiler's identity is part of the cache key
    assert "clang version" in comments["clang"] and "clang" not in comments["gcc"]


@pytest.mark.requires("clang")
def test_the_c_core_builds_with_clang_under_the_wheel_flags(tmp_path):
    """csrc/cffi_build.py's flags (-O3 -Werror ...) work with clang on every source of the core."""
    spec = importlib.util.spec_from_file_location("cffi_build", ROOT / "csrc" / "cffi_build.py")
    build = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(build)
    for source in build.SOURCES:
        includes = [arg for folder in build.INCLUDE_DIRS for arg in ("-I", str(folder))]
        r = subprocess.run(["clang", *build.C_FLAGS, "-fPIC", *includes, "-c", str(source), "-o",
                            str(tmp_path / f"{source.stem}.o")], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr


@pytest.mark.requires("clang")
def test_sanitize_with_clang_finds_the_overflow(tmp_path):
    r = crslab("sim", "--fast", "--sanitize", "--lab", LABS / "faulty" / "int_overflow.c", "--scenario",
               "hands_off", env={**os.environ, "CC": "clang"}, timeout=240)
    assert r.returncode == 3, r.stderr
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("crslab sim: int_overflow.c: UBSan: signed integer overflow: ")
    assert "at int_overflow.c:20 in lab() at tick 4583" in last
