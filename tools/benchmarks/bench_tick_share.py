"""Issue 40: how much of a tick is MuJoCo's ``mj_step``, counted in instructions by callgrind.

The default lab (Lab 1, built natively, so that callgrind sees every instruction of ``lab()`` by
name) runs the tour in this process's child under ``valgrind --tool=callgrind``, collecting only
inside the board's tick loop (``run_ticks`` in csrc/board/tick.c: the framework, ``lab()``, the
drive, friction, the hand, the log row, the serial line, the host ports and ``mj_step``). The
share is ``mj_step``'s inclusive instruction count over the loop's. Instruction counts do not
depend on the machine's load, so one run is enough. Target: >= 94 %.

Without valgrind on PATH the benchmark says so and measures nothing.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

TICKS = 6000  # past tick 4250, where the tour's hand starts moving the arm
LOOP = "run_ticks"
TARGET = 0.94

CHILD = """
import sys
from crslab.run.api import make_config
from crslab.run.inprocess import InProcessRun
InProcessRun(make_config(native=True)).run(int(sys.argv[1]))
"""


def inclusive_counts(annotated: str) -> dict[str, int]:
    """Inclusive instruction counts by function name from ``callgrind_annotate --inclusive=yes``.

    >>> inclusive_counts("  57,839,898 ( 2.85%)  ???:run_ticks [/tmp/lab.so]")
    {'run_ticks': 57839898}
    """
    counts: dict[str, int] = {}
    for line in annotated.splitlines():
        m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+\S*?:(\w+)\s", line + " ")
        if m:
            counts.setdefault(m.group(2), int(m.group(1).replace(",", "")))
    return counts


def run() -> list[str]:
    if shutil.which("valgrind") is None or shutil.which("callgrind_annotate") is None:
        return ["valgrind (callgrind) is not installed: the tick's share of mj_step not measured"]
    with tempfile.TemporaryDirectory(prefix="crslab-callgrind-") as tmp:
        out = Path(tmp) / "callgrind.out"
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                        f"--toggle-collect={LOOP}", sys.executable, "-c", CHILD, str(TICKS)],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        annotated = subprocess.run(["callgrind_annotate", "--inclusive=yes", str(out)], check=True,
                                   capture_output=True, text=True).stdout
    counts = inclusive_counts(annotated)
    loop, step = counts.get(LOOP, 0), counts.get("mj_step", 0)
    if loop == 0:
        raise RuntimeError(f"callgrind counted nothing inside {LOOP}: was the tick loop renamed?")
    share = step / loop
    verdict = "met" if share >= TARGET else "NOT met"
    return [
        f"Lab 1 tour (built natively), {TICKS} ticks under callgrind, instructions inside the tick loop:",
        f"  the loop {loop:,}; mj_step {step:,}; the rest of a tick {loop - step:,}",
        f"  mj_step's share of a tick {share:.1%} (target >= {TARGET:.0%}, issue 40: {verdict})",
    ]
