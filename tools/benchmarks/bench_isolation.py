"""Issue 5: what isolation (the worker process) and lab() timing cost: the same ticks of the
default lab on the tour, run by ``crslab sim --fast``'s code path and in-process with timing
off (crslab.run.inprocess), in one run. Target: isolated at least 0.95 of in-process."""

from __future__ import annotations

import time

from crslab.run.api import make_config
from crslab.run.assemble import started
from crslab.run.inprocess import InProcessRun
from crslab.sinks.sink import Sink

REPEATS = 5
TICKS = 25_000


def isolated_rate(config) -> float:
    with started(config) as sim:
        t = time.perf_counter()
        result = sim.run(TICKS, Sink(), speed=None)
        dt = time.perf_counter() - t
    assert result.ok
    return TICKS / dt


def in_process_rate(config) -> float:
    # the same work, minus the worker; set-up is outside the timed part on both sides
    runner = InProcessRun(config)
    t = time.perf_counter()
    out = runner.run(TICKS)
    dt = time.perf_counter() - t
    assert out
    return TICKS / dt


def run() -> list[str]:
    # the lab built natively: the worker's isolation costs the same for either firmware, and a
    # WebAssembly one run in this process would start wasmtime where every worker is forked from
    config = make_config(native=True)
    iso, inp = [], []
    for _ in range(REPEATS):  # interleaved, best of each
        iso.append(isolated_rate(config))
        inp.append(in_process_rate(config))
    a, b = max(iso), max(inp)
    return [
        f"Lab 1 tour (built natively), {TICKS} ticks, best of {REPEATS} (interleaved), set-up not timed:",
        f"  isolated (BoardRun.run --fast: worker process, lab() timed): {a:,.0f} ticks/s",
        f"  in-process (the same worker code in this process, lab() not timed): {b:,.0f} ticks/s",
        f"  ratio isolated / in-process {a / b:.3f} (target >= 0.95, issue 5)",
    ]
