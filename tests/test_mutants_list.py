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
    # a test renamed since: its mutation would stop make mutants before the first mutant
    (tmp_path / "x.toml").write_text(
        '[[mutation]]\nname = "renamed"\nfile = "tools/mutants.py"\nfind = "def load("\n'
        'replace = "def loaded("\ntests = ["tests/test_mutants_list.py::test_no_such_test"]\n'
    )
    (m,) = tool.load(tmp_path)
    assert m.problem(ROOT) == "x.toml: 'renamed': no test_no_such_test in tests/test_mutants_list.py"


def test_a_failed_test_kills_a_mutant_and_an_error_elsewhere_is_said_apart(tmp_path):
    """pytest's own report of a real run: an assertion that fails is a kill; a fixture that raises
    (as a fixture's time limit would) is an error, not a kill; both pass is a survivor."""
    import doctest
    import subprocess

    tool = _mutants()
    assert doctest.testmod(sys.modules["crslab_mutants_tool"]).failed == 0  # outcome's examples
    (tmp_path / "test_rule.py").write_text(
        "import pytest\n\n"
        "@pytest.fixture\ndef slow_setup():\n    raise TimeoutError('the fixture ran out of time')\n\n"
        "def test_assertion():\n    assert 1 + 1 == 3\n\n"
        "def test_fixture(slow_setup):\n    pass\n\n"
        "def test_fine():\n    assert True\n")

    def run(test: str) -> tuple[str, str]:
        report = tmp_path / "report.xml"
        done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--no-header",
                               f"--junitxml={report}", f"test_rule.py::{test}"], cwd=tmp_path,
                              capture_output=True, text=True, timeout=120)
        return tool.outcome(done.returncode, report.read_text(), done.stdout.strip().splitlines()[-1])

    verdict, why = run("test_assertion")
    assert verdict == "killed" and why.startswith("test_rule::test_assertion: assert (1 + 1) == 3"), why
    verdict, why = run("test_fixture")
    assert verdict == "error" and "TimeoutError: the fixture ran out of time" in why, why
    assert run("test_fine")[0] == "passed"
