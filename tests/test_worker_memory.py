"""A worker's memory is bounded, however many labs it ran (csrc/board/firmware_wasm_engine.c,
crslab/worker/main.py): it keeps the compiled modules its instances use and the last
``CRS_WASM_IDLE_MODULES`` no instance uses, and frees the one before them; a run host (and its
worker) runs a thousand distinct labs in the memory it ran the first hundred in."""

from __future__ import annotations

import json
import multiprocessing
import os
import pickle
import subprocess
import sys
from pathlib import Path

from distinct_labs import DistinctLabs
from waiting import GUARD_S

from crslab._bindings import constants
from crslab.serve.run_host import HostedRun, serve_host
from crslab.serve.wire import RUN, unhost_frame

TESTS = Path(__file__).resolve().parent

IDLE = """
import json, sys
from pathlib import Path
sys.path.insert(0, sys.argv[1])
from distinct_labs import DistinctLabs
from crslab._core import ffi, lib
from crslab.run.shared_block import SharedBlock
from crslab.worker import worker_messages
from crslab.worker.main import BoardInstances
from crslab.worker.wasm_runtime import WasmImage

labs = DistinctLabs(Path(sys.argv[2]))
kept = lib.CRS_WASM_IDLE_MODULES
configs = [labs.make(i) for i in range(1, kept + 3)]
keys = [WasmImage.read(c.build.image).digest for c in configs]
worker = BoardInstances()
blocks = [SharedBlock.new() for _ in configs]
seen = []

def note(what):
    held = [i + 1 for i, k in enumerate(keys) if lib.crs_fw_wasm_module_held(k.encode())]
    seen.append({"after": what, "modules": lib.crs_fw_wasm_module_count(), "held": held})

def opened(i):
    assert isinstance(worker.open(i, configs[i - 1], blocks[i - 1].memory, 2.0, []), worker_messages.Ready)
    worker.ran(i, 10)

opened(1)  # in use all along
for i in range(2, kept + 3):  # one after another: opened, run, stopped
    opened(i)
    worker.answer(worker_messages.Stop(i))
    note(f"stop {i}")
worker.ran(1, 20)
worker.answer(worker_messages.Stop(1))
note("stop 1")
print(json.dumps({"kept": kept, "seen": seen}))
"""
"""Run in a process of its own: wasmtime's signal handlers stay out of the test process."""


def test_a_worker_keeps_the_last_modules_no_instance_uses_and_frees_the_one_before(tmp_path):
    r = subprocess.run([sys.executable, "-c", IDLE, str(TESTS), str(tmp_path)], capture_output=True,
                       text=True, timeout=GUARD_S)
    assert r.returncode == 0, r.stderr[-3000:]
    out = json.loads(r.stdout)
    kept, seen = out["kept"], {s["after"]: s for s in out["seen"]}
    assert kept == constants.CRS_WASM_IDLE_MODULES == 8
    # lab 1 in use all along; labs 2 .. 10 opened, run and stopped one after another
    for i in range(2, kept + 2):  # up to the number kept, every one stays
        assert seen[f"stop {i}"]["modules"] == i and seen[f"stop {i}"]["held"] == list(range(1, i + 1))
    # one more that no instance uses: the least recently used of them (lab 2) goes, never lab 1
    assert seen[f"stop {kept + 2}"]["modules"] == kept + 1
    assert seen[f"stop {kept + 2}"]["held"] == [1, *range(3, kept + 3)]
    # lab 1 stopped: now the most recently used, kept; the oldest of the others (lab 3) goes
    assert seen["stop 1"]["modules"] == kept
    assert seen["stop 1"]["held"] == [1, *range(4, kept + 3)]


def resident_mb(pid: int) -> float:
    """The resident memory of process ``pid`` (the kernel's count), MB."""
    pages = int(Path(f"/proc/{pid}/statm").read_text().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE") / 2**20


def children(pid: int) -> list[int]:
    """The processes whose parent is ``pid``."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found


LABS_RUN = 1000
WARM = 100
FLAT_MB = 16.0
"""What a host and its worker may grow by from their hundredth lab to their thousandth: before the
worker forgot labs, each distinct one kept about 1 MB (its firmware's bytes, read once), some
900 MB over these 900."""


def test_a_host_runs_a_thousand_distinct_labs_in_the_memory_of_its_first_hundred(tmp_path):
    labs = DistinctLabs(tmp_path / "labs")
    folder = tmp_path / "session"
    (folder / "out").mkdir(parents=True)
    # spawned, as the server's fork server starts it: it holds no end of the pipe but its own
    spawn = multiprocessing.get_context("spawn")
    ours, theirs = spawn.Pipe()
    host = spawn.Process(target=serve_host, args=(theirs,))
    host.start()
    theirs.close()
    rss: dict[str, tuple[float, float]] = {}
    try:
        for i in range(1, LABS_RUN + 1):
            config = labs.make(i)
            ours.send((RUN, str(i), pickle.dumps(HostedRun(config, 20, None, 0.5, (), folder))))
            shown = b""
            while True:
                assert ours.poll(GUARD_S), f"lab {i}: the host sent nothing"
                key, _tag, body = unhost_frame(ours.recv_bytes())
                msg = json.loads(body)
                assert key == str(i)
                if msg["type"] == "chunk":
                    shown += "".join(text for _, text in msg["serial"]).encode("latin-1")
                if msg["type"] == "ended":
                    assert msg["status"] == "ok", msg["message"]
                    break
            assert shown == labs.printed(i)  # its own module ran, no other
            labs.remove(config)
            if i in (WARM, LABS_RUN):
                (worker,) = children(host.pid)  # type: ignore[arg-type]
                rss[str(i)] = (resident_mb(host.pid), resident_mb(worker))  # type: ignore[arg-type]
    finally:
        ours.close()
        host.join(GUARD_S)
    host_grew = rss[str(LABS_RUN)][0] - rss[str(WARM)][0]
    worker_grew = rss[str(LABS_RUN)][1] - rss[str(WARM)][1]
    assert host_grew < FLAT_MB and worker_grew < FLAT_MB, rss
