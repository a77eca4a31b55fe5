"""Issue 22: compiling a lab into its WebAssembly firmware, after zig's first use.

* **a new lab**: crslab's Lab 1 with one comment line changed each time (so nothing is cached:
  the text is new), built with ``build_lab`` into a fresh cache folder that already holds the
  framework's objects (what every build after the first reuses), in the compile sandbox as
  ``crslab sim`` builds it. Median and worst of ``REPEATS``. Target (issue 22): <= 0.3 s.
* **the same lab built natively** (``--native``, the host's C compiler, the board's objects
  cached), for comparison.
* **zig's first use** is not timed here (it is once per machine, with progress on stderr).
"""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

from crslab.lab.build import DEFAULT_LAB, build_lab
from crslab.lab.firmware import prepare_zig

REPEATS = 9


def build_s(lab: Path, cache: Path, native: bool) -> float:
    start = time.perf_counter()
    build_lab(lab, cache=cache, native=native)
    return time.perf_counter() - start


def run() -> list[str]:
    prepare_zig()
    text = DEFAULT_LAB.read_text()
    with tempfile.TemporaryDirectory(prefix="crslab-bench-build-") as tmp:
        tmp = Path(tmp)
        cache = tmp / "cache"
        cache.mkdir(mode=0o700)  # a build cache's root is the caller's to make (crslab.cache checks it)
        lab = tmp / "lab1.c"
        lab.write_text(text)
        build_lab(lab, cache=cache)  # the framework's objects, once (every later build reuses them)
        build_lab(lab, cache=cache, native=True)
        wasm, native = [], []
        for i in range(REPEATS):
            lab.write_text(f"/* build {i} */\n{text}")
            wasm.append(build_s(lab, cache, native=False))
            lab.write_text(f"/* native build {i} */\n{text}")
            native.append(build_s(lab, cache, native=True))
    return [
        f"a new lab (Lab 1, its text changed) compiled to WebAssembly firmware, sandboxed, framework "
        f"objects cached: median {statistics.median(wasm):.3f} s, worst {max(wasm):.3f} s of {REPEATS} "
        f"(target <= 0.3 s, issue 22)",
        f"the same lab built natively (host C compiler, board objects cached): median "
        f"{statistics.median(native):.3f} s, worst {max(native):.3f} s",
    ]


if __name__ == "__main__":
    print("\n".join(run()))
