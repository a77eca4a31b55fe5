"""Issue 6: throughput of ``crslab sim --fast --rrd`` and ``--csv`` against plain ``--fast`` (target >= 0.5).

Every variant runs the default Lab 1 on the tour the way a user runs it (``crslab sim`` in its own
process), interleaved, best of a few repeats, at two simulated durations. The time of a run is
the ``wall_s`` of ``--json``: from starting the worker to closing every sink, so the scopes'
start-up (rerun's import, about half a second), their last flush and the file's footer count.

* throughput: extra simulated seconds per extra wall second between the short and the long run,
  i.e. the steady rate once everything is started; the ratio to plain is the target;
* start-up: what a variant adds before its first tick and after its last (the short run's time
  minus its share at the steady rate);
* the default 25 s tour as a student runs it: run time and whole process time against plain.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
REPEATS = 3
SHORT_S, LONG_S = 25.0, 225.0


def one_run(extra: list[str], duration_s: float) -> tuple[float, float]:
    """(wall_s of the run, wall time of the whole process) for one ``crslab sim --fast``."""
    cmd = [sys.executable, "-m", "crslab", "sim", "--fast", "--json", "--no-stdin", "--duration",
           str(duration_s), *extra]
    start = time.perf_counter()
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    total = time.perf_counter() - start
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed: {r.stderr.strip()}")
    info = json.loads(r.stderr.strip().splitlines()[-1])
    return info["wall_s"], total


def run():
    with tempfile.TemporaryDirectory() as tmp:
        variants = {"plain": [], "--rrd": ["--rrd", f"{tmp}/run.rrd"], "--csv": ["--csv", f"{tmp}/run.csv"],
                    "--rrd --csv": ["--rrd", f"{tmp}/run.rrd", "--csv", f"{tmp}/run.csv"]}
        one_run([], 1.0)  # warm the lab build cache
        best = {(k, d): (float("inf"), float("inf")) for k in variants for d in (SHORT_S, LONG_S)}
        for _ in range(REPEATS):
            for duration in (SHORT_S, LONG_S):
                for name, extra in variants.items():
                    wall, total = one_run(extra, duration)
                    old = best[name, duration]
                    best[name, duration] = (min(old[0], wall), min(old[1], total))
    rate = {k: (LONG_S - SHORT_S) / (best[k, LONG_S][0] - best[k, SHORT_S][0]) for k in variants}
    setup = {k: best[k, SHORT_S][0] - SHORT_S / rate[k] for k in variants}
    run0, process0 = best["plain", SHORT_S]
    lines = [f"plain --fast: {rate['plain']:6.1f} x real time steady, {setup['plain']:.2f} s start-up; "
             f"tour ({SHORT_S:g} s) run {run0:.2f} s, process {process0:.2f} s"]
    for name in list(variants)[1:]:
        run_s, process_s = best[name, SHORT_S]
        lines.append(
            f"{name:12s}: {rate[name]:6.1f} x real time steady, ratio {rate[name] / rate['plain']:4.2f} "
            f"(target >= 0.5); start-up +{setup[name] - setup['plain']:.2f} s; tour run {run_s:.2f} s "
            f"({run0 / run_s:.2f} of plain), process {process_s:.2f} s ({process0 / process_s:.2f})")
    return lines


if __name__ == "__main__":
    print("\n".join(run()))
