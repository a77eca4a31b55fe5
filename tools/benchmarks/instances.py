"""CPU per simulated tick per board instance with many instances in one worker (a helper of
bench_sim.py; issue 32: ``crslab serve`` runs its sessions as instances of a few workers).

One WebAssembly worker (:class:`~crslab.run.board_client.BoardClient`) holds ``N`` instances of
crslab's default lab (Lab 1) on the tour and runs them all to the same tick, chunk after chunk, as
serve's run hosts do (250-tick chunks, ``PAGE_CHUNKS`` at real time, one ``RunMany`` request per
chunk). The figure is the worker's CPU time (every thread of it, Linux's schedstat) over the
ticks it ran, divided by ``N``; the first chunk (the stores' first calls) is left out. No scope
rows are logged (``--csv`` and the page's plots are outside this figure).

    python instances.py 1 50 150          # prints {"1": us, "50": us, "150": us}
    python instances.py 50 --ticks 4000 --chunk 250
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from crslab.run.api import make_config
from crslab.run.board_client import BoardClient

CHUNK_TICKS = 250
"""serve's chunk at real time (crslab.run.pacing.PAGE_CHUNKS)."""
START_TICK = 4000
"""Where the timed run starts: lab() runs from tick 4100 (the startup delay) on."""
INSTANCE_TICKS = 150_000
"""Ticks to time over all instances (a tenth of a second of CPU and more, whatever N): each
instance runs this many over N, at least 2000 and at most to the tour's end."""


def ticks_for(instances: int) -> int:
    """Ticks each of ``instances`` instances runs, the first chunk included, a whole number of
    chunks.

    >>> ticks_for(1), ticks_for(50), ticks_for(150)
    (21000, 3000, 2000)
    """
    ticks = min(25_000 - START_TICK, max(2000, INSTANCE_TICKS // instances))
    return ticks - ticks % CHUNK_TICKS


def worker_cpu_s(pid: int) -> float:
    """Seconds every thread of process ``pid`` has spent on a CPU (Linux's schedstat)."""
    tasks = Path(f"/proc/{pid}/task").iterdir()
    return sum(int((task / "schedstat").read_text().split()[0]) for task in tasks) / 1e9


def us_per_tick(instances: int, ticks: int | None = None, chunk: int = CHUNK_TICKS) -> float:
    """CPU microseconds per tick per instance of a worker running ``instances`` instances of Lab 1
    on the tour for ``ticks`` ticks each (default :func:`ticks_for`) from :data:`START_TICK`, in
    chunks of ``chunk`` ticks."""
    ticks = ticks_for(instances) if ticks is None else ticks
    config = make_config()
    worker = BoardClient()
    try:
        handles = [worker.open(config) for _ in range(instances)]
        tick, cpu0 = 0, 0.0
        for until in [START_TICK, *range(START_TICK + chunk, START_TICK + ticks + 1, chunk)]:
            if until == START_TICK + chunk:
                cpu0 = worker_cpu_s(worker.pid)  # after the run to the start and the first chunk
            for handle, ran in zip(handles, worker.run([(h, until) for h in handles])):
                handle.block.drain(lambda tick, chars: None, lambda tick, data: None)
                if getattr(ran, "tick", None) != until:
                    raise RuntimeError(f"instance {handle.id} stopped: {ran!r}")
            tick = until
        timed = tick - START_TICK - chunk
        return (worker_cpu_s(worker.pid) - cpu0) / instances / timed * 1e6
    finally:
        worker.close()


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("instances", nargs="+", type=int)
    p.add_argument("--ticks", type=int, default=None)
    p.add_argument("--chunk", type=int, default=CHUNK_TICKS)
    a = p.parse_args()
    print(json.dumps({str(n): round(us_per_tick(n, a.ticks, a.chunk), 3) for n in a.instances}))


if __name__ == "__main__":
    main()
