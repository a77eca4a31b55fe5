"""wasmtime's compilation of a firmware is kept in crslab's build cache (``compiled/``) and the next
run of the same firmware loads it instead of compiling again; a kept file wasmtime does not accept
(another wasmtime, damage) is compiled anew and replaced, and the run is the same."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from crslab.lab.firmware import MEMORY_BYTES, NATIVE_STACK_BYTES
from crslab.worker.wasm_runtime import compiled_module_path, preload

ROOT = Path(__file__).resolve().parents[1]
LAB = ROOT / "csrc" / "labs" / "lab1_kinematics.c"


@pytest.fixture
def cache(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("CRSLAB_CACHE_DIR", str(folder))
    return folder


def sim(cache: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--quiet", "--lab", str(LAB),
                           "--duration", "6"], capture_output=True, timeout=300,
                          env={**os.environ, "CRSLAB_CACHE_DIR": str(cache)})


def test_the_second_run_loads_what_the_first_compiled_and_prints_the_same(cache):
    first = sim(cache)
    assert first.returncode == 0, first.stderr.decode()[-1500:]
    [kept] = (cache / "compiled").glob("*.cwasm")
    assert kept.stat().st_size > 10_000  # machine code, not the module's bytes
    written = kept.stat().st_mtime_ns
    second = sim(cache)
    assert second.returncode == 0 and second.stdout == first.stdout
    assert kept.stat().st_mtime_ns == written  # loaded, not written again
    assert not list((cache / "compiled").glob("*.partial"))


def test_a_kept_file_wasmtime_refuses_is_compiled_anew(cache):
    first = sim(cache)
    [kept] = (cache / "compiled").glob("*.cwasm")
    kept.write_bytes(b"\x7fELF not what wasmtime wrote" + bytes(4096))
    again = sim(cache)
    assert again.returncode == 0, again.stderr.decode()[-1500:]
    assert again.stdout == first.stdout
    assert kept.read_bytes()[:4] == b"\x7fELF" and b"not what wasmtime wrote" not in kept.read_bytes()


def test_the_kept_file_is_named_by_the_module_and_the_boards_limits(cache):
    a = compiled_module_path(b"\0asm\1\0\0\0", MEMORY_BYTES, NATIVE_STACK_BYTES)
    assert a is not None and a.parent == cache / "compiled"
    assert a == compiled_module_path(b"\0asm\1\0\0\0", MEMORY_BYTES, NATIVE_STACK_BYTES)
    assert a != compiled_module_path(b"\0asm\1\0\0\0 ", MEMORY_BYTES, NATIVE_STACK_BYTES)
    assert a != compiled_module_path(b"\0asm\1\0\0\0", MEMORY_BYTES * 2, NATIVE_STACK_BYTES)


def test_wasmtime_can_be_loaded_ahead_of_forks():
    assert preload() is True


@pytest.mark.parametrize("board", [[], ["--native"]], ids=["wasm", "native"])
def test_a_lab_cannot_write_the_kept_code_the_board_loads(cache, tmp_path, board):
    """The board runs what it finds in ``compiled/`` as machine code: a lab that tries to replace
    it (the write is in lab(), at tick 5123) is stopped, and the file is as the board wrote it."""
    assert sim(cache).returncode == 0
    [kept] = (cache / "compiled").glob("*.cwasm")
    before = kept.read_bytes()
    hostile = tmp_path / "write_file.c"
    hostile.write_text((ROOT / "tests" / "labs" / "hostile" / "write_file.c").read_text()
                       .replace("TARGET_PATH", str(kept)))
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--quiet", "--lab", str(hostile),
                        "--duration", "5.2", *board], capture_output=True, text=True, timeout=300,
                       env={**os.environ, "CRSLAB_CACHE_DIR": str(cache)})
    assert r.returncode == 3, r.stderr[-1500:]
    assert f"was stopped by the sandbox: it tried to open {kept} for writing" in r.stderr
    assert kept.read_bytes() == before
