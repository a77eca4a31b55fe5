"""Issue 6: throughput of ``crslab sim --fast --rrd`` and ``--csv`` against plain ``--fast`` (target >= 0.5).

Each variant runs the default Lab 1 on the tour as the user would (``crslab sim`` in its own
process), for a short and a long simulated time, best of a few interleaved repeats. Throughput is
simulated seconds per wall-clock second of the run (``wall_s`` of ``--json``: from starting the
worker to closing every sink, so rerun's start-up, the last flush and the file's footer count).
The long run shows the steady rate; the short one what a student's default run costs in all.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CRSLAB = [sys.executable, "-m", "crslab"]
REPEATS = 3


def one_run(extra: list[str], duration_s: float) -> tuple[float, float]:
    """(wall_s of the run, wall time of the whole process) for one ``crslab sim --fast``."""
    cmd = [*CRSLAB, "sim", "--fast", "--json", "--no-stdin", "--duration", str(duration_s), *extra]
    start = time.perf_counter()
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    total = time.perf_counter() - start
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed: {r.stderr.strip()}")
    info = json.loads(r.stderr.strip().splitlines()[-1])
    return info["wall_s"], total


def run():
    lines = []
    with tempfile.TemporaryDirectory() as tmp:
        variants = {"plain": [], "--rrd": ["--rrd", f"{tmp}/run.rrd"], "--csv": ["--csv", f"{tmp}/run.csv"],
                    "--rrd --csv": ["--rrd", f"{tmp}/run.rrd", "--csv", f"{tmp}/run.csv"]}
        one_run([], 1.0)  # warm the lab build cache
        for duration in (25.0, 200.0):
            best = {k: (float("inf"), float("inf")) for k in variants}
            for _ in range(REPEATS):
                for name, extra in variants.items():
                    wall, total = one_run(extra, duration)
                    best[name] = (min(best[name][0], wall), min(best[name][1], total))
            plain_wall, plain_total = best["plain"]
            lines.append(f"{duration:g} s simulated: plain {duration / plain_wall:6.1f} x real time "
                         f"(run {plain_wall:.2f} s, process {plain_total:.2f} s)")
            for name in list(variants)[1:]:
                wall, total = best[name]
                lines.append(f"  {name:12s} {duration / wall:6.1f} x real time   "
                             f"ratio {plain_wall / wall:4.2f} (target >= 0.5); "
                             f"whole process {plain_total / total:4.2f}")
    return lines


if __name__ == "__main__":
    print("\n".join(run()))
