"""Issues 6 and 19: what the scope sinks cost a student's run: ``crslab sim --fast --rrd`` and
``--csv`` against plain ``--fast``.

Every variant runs the default Lab 1 on the tour the way a user runs it (``crslab sim`` in its own
process), interleaved, best of ``REPEATS``, at two simulated durations: the 25 s tour and a
225 s run. Two times are taken of each run:

* **run**: the ``wall_s`` of its ``--json`` summary, from starting the worker to closing every
  sink, so the scopes' start-up (rerun's import, about half a second), their last flush and the
  file's footer count; the summary is the stderr line that is a JSON object (a warning may
  follow it);
* **process**: from process start to exit (stdout to a file), as the student waits for it.

Per variant, printed:

* the headline, the **whole tour** (25 s): plain's run time over the variant's, i.e. the share
  of plain's speed the variant keeps on a student's run. Target (issue 19): >= 0.7;
* the same ratio of process times;
* the **steady rate**: extra simulated seconds per extra run second between the 25 s and the
  225 s run, i.e. the throughput once everything is started, and its ratio to plain's.
  Target (issue 6): >= 0.5;
* **start-up**: what the variant adds before its first tick and after its last (its tour run
  time minus the tour's share at its steady rate, less plain's).
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
TOUR_S, LONG_S = 25.0, 225.0
TOUR_TARGET, STEADY_TARGET = 0.7, 0.5


def json_summary(stderr: str) -> dict:
    """The ``--json`` summary among ``crslab sim``'s stderr lines: the one that is a JSON object
    with ``wall_s`` (announcements may come before it, warnings after it).

    >>> json_summary('crslab sim: note\\n{"status": "ok", "wall_s": 0.5}\\ncrslab sim: warning: x\\n')
    {'status': 'ok', 'wall_s': 0.5}
    """
    for line in reversed(stderr.splitlines()):
        if line.startswith("{"):
            try:
                info = json.loads(line)
            except ValueError:
                continue
            if isinstance(info, dict) and "wall_s" in info:
                return info
    raise ValueError(f"no --json summary line in crslab sim's stderr: {stderr[-2000:]!r}")


def one_run(extra: list[str], duration_s: float, out_dir: str) -> tuple[float, float]:
    """(run time from ``--json``, process start to exit) of one ``crslab sim --fast``, its stdout
    to a file."""
    cmd = [sys.executable, "-m", "crslab", "sim", "--fast", "--json", "--no-stdin", "--duration",
           str(duration_s), *extra]
    with open(Path(out_dir) / "stdout.txt", "wb") as out:
        start = time.perf_counter()
        r = subprocess.run(cmd, cwd=ROOT, stdout=out, stderr=subprocess.PIPE, text=True,
                           stdin=subprocess.DEVNULL)
        total = time.perf_counter() - start
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed: {r.stderr.strip()}")
    return json_summary(r.stderr)["wall_s"], total


def run():
    with tempfile.TemporaryDirectory() as tmp:
        variants = {"plain": [], "--rrd": ["--rrd", f"{tmp}/run.rrd"], "--csv": ["--csv", f"{tmp}/run.csv"],
                    "--rrd --csv": ["--rrd", f"{tmp}/run.rrd", "--csv", f"{tmp}/run.csv"]}
        one_run([], 1.0, tmp)  # warm the lab build cache
        best = {(k, d): (float("inf"), float("inf")) for k in variants for d in (TOUR_S, LONG_S)}
        for _ in range(REPEATS):
            for duration in (TOUR_S, LONG_S):
                for name, extra in variants.items():
                    wall, total = one_run(extra, duration, tmp)
                    old = best[name, duration]
                    best[name, duration] = (min(old[0], wall), min(old[1], total))
    rate = {k: (LONG_S - TOUR_S) / (best[k, LONG_S][0] - best[k, TOUR_S][0]) for k in variants}
    setup = {k: best[k, TOUR_S][0] - TOUR_S / rate[k] for k in variants}
    run0, process0 = best["plain", TOUR_S]
    lines = [f"plain --fast, whole {TOUR_S:g} s tour, best of {REPEATS}: run (worker start to sinks "
             f"closed) {run0:.2f} s, process (start to exit) {process0:.2f} s; steady "
             f"{rate['plain']:.1f} x real time ({LONG_S:g} s vs {TOUR_S:g} s runs), "
             f"start-up {setup['plain']:.2f} s"]
    for name in list(variants)[1:]:
        run_s, process_s = best[name, TOUR_S]
        steady, extra_s = rate[name] / rate["plain"], setup[name] - setup["plain"]
        lines += [
            f"{name}: whole {TOUR_S:g} s tour, plain's run time / this one's: {run0 / run_s:.2f} "
            f"(target >= {TOUR_TARGET}, issue 19) [{run_s:.2f} s vs {run0:.2f} s]; process time ratio "
            f"{process0 / process_s:.2f} [{process_s:.2f} s vs {process0:.2f} s]",
            f"{' ' * len(name)}  steady rate {rate[name]:.1f} x real time, {steady:.2f} of plain's "
            f"(target >= {STEADY_TARGET}, issue 6); start-up {extra_s:+.2f} s over plain's",
        ]
    return lines


if __name__ == "__main__":
    print("\n".join(run()))
