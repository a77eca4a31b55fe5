"""``make bench``'s modules load (tools/benchmarks/bench_*.py): a file a benchmark reads or a module
it imports that moved is found by the suite, not by the next person to run the benchmarks."""

import importlib.util
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "tools" / "benchmarks"


@pytest.mark.parametrize("path", sorted(BENCHMARKS.glob("bench_*.py")), ids=lambda p: p.stem)
def test_each_benchmark_module_loads_and_has_its_run(path, monkeypatch):
    monkeypatch.syspath_prepend(str(BENCHMARKS))  # the benchmarks' helper modules, as tools/bench.py does
    spec = importlib.util.spec_from_file_location(f"_bench_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert callable(module.run)
    sys.modules.pop(f"_bench_{path.stem}", None)
