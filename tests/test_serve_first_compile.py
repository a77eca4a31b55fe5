"""A lab's first run in ``crslab serve``: its session process has wasmtime compile the firmware into
the build cache (crslab/serve/page_process.py ``compile_module``), with no run, worker or board
instance, so that the run host's shared worker only loads it."""

import multiprocessing
import os

import pytest

from crslab.run.api import make_config
from crslab.run.board_run import BoardRun
from crslab.serve.page_process import compile_module
from crslab.starters import starter_text
from crslab.worker.wasm_runtime import ENGINE_ENVIRONMENT, NotCompiled, WasmImage, compile_kept


@pytest.fixture
def config(tmp_path, monkeypatch):
    monkeypatch.setenv("CRSLAB_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("WASMTIME_BACKTRACE_DETAILS", raising=False)  # compile_kept sets what it needs
    lab = tmp_path / "lab1.c"
    lab.write_text(starter_text("lab1", "A"))
    return make_config(lab, "tour")


def test_the_first_compile_starts_no_process_and_the_run_loads_what_it_kept(config, monkeypatch):
    kept = WasmImage.read(config.build.image).compiled_path()
    assert kept is not None and not kept.exists()

    def no_process(self):  # noqa: ANN001, ANN202
        raise AssertionError("the first compile started a process")

    with monkeypatch.context() as m:
        m.setattr(multiprocessing.process.BaseProcess, "start", no_process)
        compile_module(config)
    assert kept.stat().st_size > 10_000 and kept.with_name(kept.name + ".seal").exists()
    # its engine was made with the workers' environment (unset before it): a worker started apart,
    # as a run host's is, would refuse a module compiled otherwise and compile it on every run (this
    # test's worker is forked from here, engine and all, so its run alone cannot tell)
    assert {k: os.environ.get(k) for k in ENGINE_ENVIRONMENT} == ENGINE_ENVIRONMENT
    written = (kept.stat().st_ino, kept.stat().st_mtime_ns)
    with BoardRun(config) as sim:
        result = sim.run(5000)
    assert result.status == "ok" and result.end_tick == 5000
    # loaded as it was kept: a module the board's engine could not load would be compiled anew and
    # written again (an engine made otherwise, e.g. without wasmtime's environment, is refused)
    assert (kept.stat().st_ino, kept.stat().st_mtime_ns) == written
    compile_module(config)  # kept already: nothing is compiled or written
    assert (kept.stat().st_ino, kept.stat().st_mtime_ns) == written


def test_a_kept_file_that_is_not_this_users_is_compiled_again(config):
    kept = WasmImage.read(config.build.image).compiled_path()
    kept.parent.mkdir(parents=True, exist_ok=True)
    kept.write_bytes(b"planted" * 4000)  # no seal of this user's: never loaded
    compile_module(config)
    assert b"planted" not in kept.read_bytes() and kept.with_name(kept.name + ".seal").exists()


def test_what_wasmtime_cannot_compile_is_said(tmp_path):
    image = WasmImage(b"\0asm\x01\0\0\0 not a module", "0" * 32, 1 << 20, 1 << 20)
    with pytest.raises(NotCompiled, match="not a WebAssembly module wasmtime can run"):
        compile_kept(image, tmp_path / "x.cwasm")
    assert not os.path.exists(tmp_path / "x.cwasm")
