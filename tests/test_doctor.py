"""``crslab doctor``: exit 0 where `crslab sim` works; with a PATH that hides every compiler it
names the missing host compiler (which only --native, --sanitize and crslab debug need) and how to
install one, and still exits 0: the WebAssembly board needs none."""

import os
import shutil
import subprocess
import sys

import pytest

from crslab.lab.compiler import INSTALL_HINT

CC_ITEM = "C compiler for --native, --sanitize and crslab debug"
WASM_ITEM = "WebAssembly compiler and runtime"
ITEMS = ["platform", "Python", WASM_ITEM, "build cache", "lab build", "MuJoCo", "simulation", CC_ITEM,
         "sandbox", "display for --viewer", "rerun viewer", "pseudo-terminals for --pty",
         "debugger for crslab debug"]
REQUIRED = ITEMS[:7]


def doctor(env=None, cwd=None):
    r = subprocess.run([sys.executable, "-m", "crslab", "doctor"], capture_output=True, text=True,
                       timeout=180, env={**os.environ, **(env or {})}, cwd=cwd)
    lines = r.stdout.splitlines()
    items = {line[9:].split(":", 1)[0]: line for line in lines}
    return r, items


def test_doctor_exits_0_where_sim_runs(tmp_path):
    r, items = doctor(cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert list(items) == ITEMS
    for name in REQUIRED:
        assert items[name].startswith("ok       "), items[name]
    assert "lab1_kinematics.c compiles to a WebAssembly firmware" in items["lab build"]
    assert "printed 6 lines" in items["simulation"]  # Lab 1 prints three lines at 0 and 0.5 s
    assert "firmware ran 0.6 s on the board" in items["simulation"]
    assert items[WASM_ITEM].startswith(f"ok       {WASM_ITEM}: zig ")
    assert items["sandbox"].startswith("ok       sandbox: Landlock ABI ")
    if shutil.which("gdb"):  # an optional item: CI has gdb (test_debug_gdb.py needs it)
        assert items["debugger for crslab debug"].startswith("ok       debugger for crslab debug: GNU gdb ")
    assert r.stderr.strip() == "crslab doctor: everything 'crslab sim' needs is here"


def test_doctor_names_the_fix_when_no_compiler_is_on_path(tmp_path):
    r, items = doctor(env={"PATH": str(tmp_path), "CC": ""})
    assert r.returncode == 0, r.stdout
    assert items[CC_ITEM] == (f"missing  {CC_ITEM}: no C compiler on PATH (tried cc, gcc, clang); fix: "
                              + INSTALL_HINT)
    assert "sudo apt install gcc" in items[CC_ITEM]
    assert items["lab build"].startswith("ok ") and items["simulation"].startswith("ok ")
    assert items["MuJoCo"].startswith("ok ") and items["build cache"].startswith("ok ")
    assert "Traceback" not in r.stdout + r.stderr


def test_doctor_reports_an_unusable_cache(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    r, items = doctor(env={"CRSLAB_CACHE_DIR": str(blocker / "cache")})
    assert r.returncode == 1
    assert items["build cache"] == (f"FAILED   build cache: CRSLAB_CACHE_DIR={blocker / 'cache'} cannot be "
                                    "used as crslab's cache: it cannot be made (Not a directory); fix: set "
                                    "CRSLAB_CACHE_DIR to a folder you can write")


@pytest.mark.requires("clang")
def test_doctor_names_the_compiler_cc_chooses():
    r, items = doctor(env={"CC": "clang"})
    assert r.returncode == 0, r.stdout
    assert items[CC_ITEM].startswith(f"ok       {CC_ITEM}: clang (clang ")
