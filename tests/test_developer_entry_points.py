"""What a developer meets first: ``make help``'s words, the README's promise of how long ``make
test`` takes, and an editable install that sets up without setuptools' boxed warning."""

import re
import subprocess
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.requires("make")
def test_make_help_says_what_each_target_does_in_a_newcomers_words():
    out = subprocess.run(["make", "-s", "help"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    bench = next(line for line in out.splitlines() if line.strip().startswith("make bench"))
    assert "issues" not in bench and "beside its target" in bench, bench


def test_the_readme_says_how_long_make_test_takes():
    readme = (ROOT / "README.md").read_text().splitlines()
    line = next(line for line in readme if line.startswith("make test"))
    assert re.search(r"about \d+ minutes", line), line


def test_an_editable_install_is_a_plain_path_entry():
    """setuptools warns (a boxed text on every ``make sim``) unless the packages sit where their
    names say under a declared root: then its editable install is a .pth of this folder, which
    needs no import hook and says nothing. Its own test of the layout decides which it does."""
    from setuptools import find_packages
    from setuptools.command.editable_wheel import _simple_layout

    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    package_dir = config["package-dir"]
    assert set(package_dir) == {""}  # the condition beside _simple_layout in setuptools' choice
    packages = find_packages(str(ROOT / package_dir[""]), include=config["packages"]["find"]["include"])
    assert "crslab" in packages and "crslab.run" in packages
    assert _simple_layout(packages, package_dir, ROOT)


def test_the_suite_waits_for_the_webassembly_compiler_before_its_first_test():
    """conftest's session fixture built zig's C library before any test ran: no fixture's time
    limit includes that first build."""
    from crslab.lab.firmware import is_zig_prepared

    assert is_zig_prepared()


def test_every_file_the_suite_runs_first_exists():
    """tests/conftest.py's list of the longest files (run first, so make test's two workers end
    together) names files that are there: a renamed file would silently lose its place."""
    from conftest import SLOW_FIRST

    tests = Path(__file__).parent
    assert [name for name in SLOW_FIRST if not (tests / name).is_file()] == []
    assert len(set(SLOW_FIRST)) == len(SLOW_FIRST)
