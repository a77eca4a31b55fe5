"""``make bench``'s modules load (tools/benchmarks/bench_*.py): a file a benchmark reads or a module
it imports that moved is found by the suite, not by the next person to run the benchmarks."""

import importlib.util
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "tools" / "benchmarks"


def load(path: Path, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.syspath_prepend(str(BENCHMARKS))  # the benchmarks' helper modules, as tools/bench.py does
    spec = importlib.util.spec_from_file_location(f"_bench_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("path", sorted(BENCHMARKS.glob("bench_*.py")), ids=lambda p: p.stem)
def test_each_benchmark_module_loads_and_has_its_run(path, monkeypatch):
    module = load(path, monkeypatch)
    assert callable(module.run)
    sys.modules.pop(f"_bench_{path.stem}", None)


def test_the_firmware_benchmark_builds_in_a_cache_of_its_own(monkeypatch):
    # one build of each kind: the benchmark's own cache folder is one crslab.cache accepts (its root
    # left unmade, every build failed and make bench with it)
    module = load(BENCHMARKS / "bench_firmware.py", monkeypatch)
    monkeypatch.setattr(module, "REPEATS", 1)
    lines = module.run()
    assert len(lines) == 2 and "median" in lines[0] and "built natively" in lines[1]
