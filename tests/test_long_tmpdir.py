"""A long $TMPDIR (a CI runner's, pytest's) is a folder like any other: no run hands a descriptor
to its worker through a socket there (a socket's path holds at most 107 bytes)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LAB = ROOT / "csrc" / "labs" / "lab1_kinematics.c"


@pytest.fixture
def long_tmpdir(tmp_path):
    folder = tmp_path / ("a-long-temporary-folder-" + "t" * 60)
    folder.mkdir()
    assert len(str(folder)) > 100
    return {**os.environ, "TMPDIR": str(folder)}


@pytest.mark.parametrize("board", [[], ["--native"], ["--sanitize"]], ids=["wasm", "native", "sanitize"])
def test_sim_runs_with_a_long_tmpdir(long_tmpdir, board):
    def run(env: dict) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--quiet", "--lab", str(LAB),
                               "--duration", "4.2", *board],
                              capture_output=True, text=True, timeout=300, env=env)

    r = run(long_tmpdir)
    assert r.returncode == 0, r.stderr[-1500:]
    assert r.stdout.count("\n") >= 2 and r.stdout == run(dict(os.environ)).stdout  # what it prints anywhere


def test_grade_runs_with_a_long_tmpdir(long_tmpdir, tmp_path):
    subs = tmp_path / "class"
    subs.mkdir()
    for name in ("a.c", "b.c"):
        (subs / name).write_bytes(LAB.read_bytes())
    r = subprocess.run([sys.executable, "-m", "crslab", "grade", str(subs), "--reference", str(LAB),
                        "--duration", "4.2", "--jobs", "2", "-o", str(tmp_path / "grades")],
                       capture_output=True, text=True, timeout=300, env=long_tmpdir)
    assert r.returncode == 0, r.stderr[-1500:]
    assert "2 pass" in r.stdout + r.stderr
