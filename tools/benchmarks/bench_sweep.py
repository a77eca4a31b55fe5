"""Issue 16: sweep throughput. 64 short runs (crslab's Lab 1 on hands_off, 2 s simulated, no
startup delay, each with its own friction and payload) as ``crslab sweep`` runs them, with 1 and
2 local workers and on a 2-worker Dask LocalCluster (started before the clock). Best of
``REPEATS`` interleaved rounds. Targets: 2 workers >= 1.7x one worker; Dask within 15 % of the
local pool (runs/s ratio >= 0.85). On a 2-core machine shared with other work the ratios are only
as good as the quiet the machine had: the load average is printed beside them."""

from __future__ import annotations

import logging
import os
import time

from crslab.executors.dask_cluster import DaskExecutor
from crslab.executors.local import LocalExecutor
from crslab.lab.build import DEFAULT_LAB
from crslab.lab.source import LabSource
from crslab.run.api import make_config
from crslab.sweep import sampling, variations
from crslab.sweep.sample_job import SweepJob, SweepSpec

RUNS = 64
DURATION_TICKS = 2000
REPEATS = 3


def jobs() -> list[SweepJob]:
    config = make_config(None, "hands_off", startup_delay=False)
    varies = tuple(
        variations.check(
            [variations.parse_vary("friction=0.6:1.4"), variations.parse_vary("payload_kg=0:1.5")],
            config.build.watched,
            "lab",
        )
    )
    spec = SweepSpec(LabSource.read(DEFAULT_LAB), config, DURATION_TICKS, varies, seed=1)
    units = sampling.samples("lhs", len(varies), n=RUNS, seed=1)
    return [
        SweepJob(spec, i, tuple(v.value_at(float(u)) for v, u in zip(varies, row, strict=True)))
        for i, row in enumerate(units)
    ]


def rate(executor, batch) -> float:
    rows = []
    t = time.perf_counter()
    executor.run(batch, lambda i, row: rows.append(row))
    dt = time.perf_counter() - t
    assert len(rows) == len(batch) and all(r["status"] == "ok" for r in rows), {r["status"] for r in rows}
    return len(batch) / dt


def run() -> list[str]:
    logging.getLogger("distributed").setLevel(logging.ERROR)
    batch = jobs()
    one, two = LocalExecutor(1), LocalExecutor(2)
    dask = DaskExecutor("local:2")
    try:
        rate(two, batch[:4])  # warm: the fork server, the build cache
        dask.run(batch[:4], lambda i, r: None)
        best = {"1 local": 0.0, "2 local": 0.0, "dask": 0.0}
        for _ in range(REPEATS):
            best["1 local"] = max(best["1 local"], rate(one, batch))
            best["2 local"] = max(best["2 local"], rate(two, batch))
            best["dask"] = max(best["dask"], rate(dask, batch))
    finally:
        dask.close()
    load = os.getloadavg()
    return [
        f"{RUNS} runs of Lab 1 on hands_off, {DURATION_TICKS / 1000:g} s simulated each, friction, payload "
        f"varied; best of {REPEATS} (interleaved); load average {load[0]:.2f} {load[1]:.2f} "
        f"on {os.cpu_count()} cores:",
        f"  1 local worker:              {best['1 local']:6.1f} runs/s",
        f"  2 local workers:             {best['2 local']:6.1f} runs/s",
        f"  Dask LocalCluster, 2 workers: {best['dask']:6.1f} runs/s",
        f"  2 workers / 1 worker {best['2 local'] / best['1 local']:.2f} (target >= 1.7, issue 16)",
        f"  Dask / local pool (2 workers) {best['dask'] / best['2 local']:.2f} (target >= 0.85, issue 16)",
    ]
