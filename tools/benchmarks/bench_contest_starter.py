"""Issue 30: what the final project's contest run of crslab's own starter costs, in CPU time
(bench_contest.py times the simulation in the contest world against a bare mj_step loop).

``crslab new final`` writes the starter into a temporary folder; one ``crslab contest --lab
final.c --json`` builds it (the build is cached by content, so the runs after it do not build);
then ``REPEATS`` runs as a student runs it, each in its own process. Printed: the CPU time
(user + system) of the process and everything it waited for (the worker: MuJoCo and the
firmware), best and median, against the target (< 2 s), and the tasks the run completed; beside
it the CPU time of ``crslab contest --help`` in the same way (the command's start: Python, numpy,
MuJoCo, the parser), so the run's own share shows.
"""

from __future__ import annotations

import json
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

REPEATS = 3
TARGET_CPU_S = 2.0


def children_cpu_s() -> float:
    """User + system CPU seconds of every child process waited for so far."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def contest(lab: Path) -> tuple[float, dict]:
    """One ``crslab contest --json`` run: its CPU seconds and its scorecard."""
    before = children_cpu_s()
    r = subprocess.run([sys.executable, "-m", "crslab", "contest", "--lab", str(lab), "--json"],
                       capture_output=True, text=True, timeout=600)
    cpu = children_cpu_s() - before
    if r.returncode not in (0, 1):
        raise RuntimeError(f"crslab contest failed ({r.returncode}): {r.stderr[-2000:]}")
    return cpu, json.loads(r.stdout)


def help_cpu_s() -> float:
    """The CPU seconds of ``crslab contest --help``: starting the command, running nothing."""
    before = children_cpu_s()
    subprocess.run([sys.executable, "-m", "crslab", "contest", "--help"], capture_output=True, check=True,
                   timeout=120)
    return children_cpu_s() - before


def run() -> list[str]:
    with tempfile.TemporaryDirectory(prefix="crslab-bench-contest-") as folder:
        lab = Path(folder) / "final.c"
        subprocess.run([sys.executable, "-m", "crslab", "new", "final", str(lab)], check=True,
                       capture_output=True, timeout=120)
        contest(lab)   # builds the lab once (cached by content)
        times, starts, card = [], [], {}
        for _ in range(REPEATS):
            cpu, card = contest(lab)
            times.append(cpu)
            starts.append(help_cpu_s())
    done = [t for t, v in card["tasks"].items() if v["done"]]
    best, median = min(times), statistics.median(times)
    verdict = "meets" if median < TARGET_CPU_S else "MISSES"
    return [
        f"crslab contest on the starter (crslab new final), whole process: {best:.2f} s CPU best, "
        f"{median:.2f} s median of {REPEATS} (target < {TARGET_CPU_S:g} s, issue 30: {verdict})",
        "of which starting the command (crslab contest --help): "
        f"{statistics.median(starts):.2f} s CPU median",
        f"its card: {len(done)} of 4 tasks done ({', '.join(done) or 'none'}), time "
        + ("-" if card["time_s"] is None else f"{card['time_s']:.2f} s"),
    ]
