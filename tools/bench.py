"""``make bench``: run every tools/benchmarks/bench_*.py in one process and print its ratios.

Each benchmark module has ``run() -> list[str]`` returning the lines to print; every line says
what it measures and, beside a ratio, the target an issue set. A benchmark that fails prints its
error and the run exits non-zero after the others have run. Other modules in ``benchmarks/``
(no ``bench_`` prefix) are helpers the benchmarks import. ``python tools/bench.py sim scopes``
runs only those; options after the names go to each benchmark named (its ``run(options)``):
``python tools/bench.py serve --sessions 300``.
"""

from __future__ import annotations

import importlib.util
import sys
import time
import traceback
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "benchmarks"))  # the benchmarks' helper modules


def main() -> int:
    args = sys.argv[1:]
    if args in (["-h"], ["--help"]):
        names = " ".join(sorted(p.stem.removeprefix("bench_") for p in HERE.glob("benchmarks/bench_*.py")))
        print(f"usage: tools/bench.py [NAME ...] [OPTIONS]\n\n{__doc__.strip()}\n\nbenchmarks: {names}")
        return 0
    first_option = next((i for i, a in enumerate(args) if a.startswith("-")), len(args))
    only, options = args[:first_option], args[first_option:]
    if options and not only:
        print("bench: options go to the benchmarks named before them (tools/bench.py serve --sessions 300)",
              file=sys.stderr)
        return 2
    failed = 0
    for path in sorted((HERE / "benchmarks").glob("bench_*.py")):
        name = path.stem.removeprefix("bench_")
        if only and name not in only:
            continue
        spec = importlib.util.spec_from_file_location(path.stem, path)
        module = importlib.util.module_from_spec(spec)
        assert spec.loader is not None
        print(f"== {name}", flush=True)
        start = time.perf_counter()
        try:
            spec.loader.exec_module(module)
            for line in (module.run(options) if options else module.run()):
                print(f"   {line}", flush=True)
        except Exception:  # noqa: BLE001 - report and go on with the other benchmarks
            traceback.print_exc()
            failed += 1
        print(f"   ({time.perf_counter() - start:.1f} s)", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
