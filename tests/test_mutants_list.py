"""The mutation list of ``make mutants`` (tools/mutants.py) stays applicable as the code moves.

``make mutants`` itself is too slow for CI; this checks, in a second, that every listed mutation
still finds its one line in today's code and names tests that exist, so that the list never
rots into mutations that silently apply to nothing.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _mutants():
    spec = importlib.util.spec_from_file_location("crslab_mutants_tool", ROOT / "tools" / "mutants.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while it loads
    assert spec.loader is not None
    spec.loader.exec_module(module)
    return module


def test_every_mutation_applies_to_exactly_one_line_of_todays_code():
    tool = _mutants()
    mutations = tool.load()
    assert [p for m in mutations if (p := m.problem(ROOT)) is not None] == []
    assert len({m.name for m in mutations}) == len(mutations), "two mutations share a name"


def test_a_stale_mutation_is_named_with_why(tmp_path):
    tool = _mutants()
    (tmp_path / "x.toml").write_text(
        '[[mutation]]\nname = "gone"\nfile = "crslab/regress/compare.py"\nfind = "no such text"\n'
        'replace = "y"\ntests = ["tests/test_regress_compare.py"]\n'
    )
    (m,) = tool.load(tmp_path)
    assert m.problem(ROOT) == (
        "x.toml: 'gone': 'no such text' occurs 0 times in crslab/regress/compare.py (must be once)"
    )
