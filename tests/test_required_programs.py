"""A test marked ``requires(PROGRAM)`` (tests/conftest.py) is skipped, or under
``CRSLAB_REQUIRE_ALL=1`` failed with the program's name, before any of its fixtures is set up: a
module's browser or nginx, started once for all its tests, must not meet the missing program first
(a fresh machine without Chromium had every browser test error out on Playwright's launch)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
MISSING = "crslab-test-no-such-program"
TESTS = f'''
import pytest

@pytest.fixture(scope="module")
def server():
    raise RuntimeError("the module's server was started")

@pytest.mark.requires("{MISSING}")
def test_needs_the_program(server):
    pass

def test_needs_nothing():
    pass
'''


def run(tmp_path: Path, require_all: bool) -> subprocess.CompletedProcess:
    (tmp_path / "test_marked.py").write_text(TESTS)
    env = {k: v for k, v in os.environ.items() if k != "CRSLAB_REQUIRE_ALL"}
    if require_all:
        env["CRSLAB_REQUIRE_ALL"] = "1"
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-rA", "-p", "no:cacheprovider",
                           "-p", "tests.conftest", "--rootdir", str(tmp_path), "-c", os.devnull,
                           str(tmp_path / "test_marked.py")],
                          cwd=REPO, env=env, capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("require_all", [False, True], ids=["a_user", "ci"])
def test_a_missing_program_is_met_before_the_fixtures(tmp_path, require_all):
    r = run(tmp_path, require_all)
    assert "the module's server was started" not in r.stdout, r.stdout
    if require_all:
        assert r.returncode == 1, r.stdout
        assert f"CRSLAB_REQUIRE_ALL=1 but {MISSING} is not installed" in r.stdout
        assert "1 passed" in r.stdout and "1 error" in r.stdout
    else:
        assert r.returncode == 0, r.stdout
        assert f"needs {MISSING} (not installed)" in r.stdout
        assert "1 passed" in r.stdout and "1 skipped" in r.stdout
