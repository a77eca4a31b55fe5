"""crslab's rate on the tour in a process of its own (a helper of bench_sim.py).

Every worker a process forks shares that process's address-space layout (Linux places its
libraries and mappings at random, ASLR), and crslab's tick runs code in several libraries (the
board, wasmtime, the firmware, MuJoCo): the same build measured 267,000-319,000 ticks/s from one
process to the next, and steadily within one (``setarch -R``, one fixed layout: 312,000-332,000).
The bare C loop the rate is compared with runs in a new process every time; so crslab's runs are
taken in new processes too, one run of each kind per process, and both sides sample as many
layouts.

    python sim_rates.py   # prints {"wasm": [wall, cpu], "native": [wall, cpu]} (ticks/s)
    python sim_rates.py WORLD SCENARIO   # the same for the default lab on SCENARIO in WORLD
"""

from __future__ import annotations

import json
import time
from pathlib import Path

from crslab.run.api import make_config
from crslab.run.board_run import BoardRun
from crslab.sinks.sink import Sink


def on_cpu_s(pid: int) -> float | None:
    """Seconds process ``pid`` has spent on a CPU (Linux's schedstat), None elsewhere."""
    try:
        return int(Path(f"/proc/{pid}/schedstat").read_text().split()[0]) / 1e9
    except (OSError, ValueError, IndexError):
        return None


def sim_rate(config, ticks: int) -> tuple[float, float | None]:
    """Ticks per second of BoardRun.run over ``ticks`` ticks (the worker already running), by
    wall time and by the worker's CPU time (None where it cannot be read)."""
    with BoardRun(config) as sim:
        cpu0 = on_cpu_s(sim.worker_pid)
        t = time.perf_counter()
        result = sim.run(ticks, Sink(), speed=None)
        dt = time.perf_counter() - t
        cpu1 = on_cpu_s(sim.worker_pid)
    assert result.ok, result.message
    return ticks / dt, (ticks / (cpu1 - cpu0) if cpu0 is not None and cpu1 is not None else None)


def main() -> None:
    import sys

    world, scenario = (sys.argv[1], sys.argv[2]) if len(sys.argv) == 3 else (None, None)
    wasm = make_config(None, scenario, world=world)
    native = make_config(None, scenario, world=world, native=True)
    ticks = wasm.scenario.end_tick
    print(json.dumps({"wasm": sim_rate(wasm, ticks), "native": sim_rate(native, ticks)}))


if __name__ == "__main__":
    main()
