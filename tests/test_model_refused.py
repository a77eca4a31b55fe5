"""A model MuJoCo refuses is blamed on the file that made it (issue 38: ``mass_kg = 1e-300`` was
refused by MuJoCo but blamed on the lab, ``crashed``, exit status 3): a world whose every value is in
range but whose peg MuJoCo cannot simulate (1e-9 m across: its inertia's eigenvalues round to zero)
is one line naming the world file, exit status 2 (bad input), on either board."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from crslab.world import load_world

ROOT = Path(__file__).resolve().parents[1]
CONTEST = ROOT / "crslab" / "worlds" / "contest.toml"


def world_with_peg_diameter(tmp_path: Path, diameter: str) -> Path:
    text = CONTEST.read_text()
    assert "\n[peg]\ndiameter_m = 0.010 " in text
    path = tmp_path / "bench.toml"
    path.write_text(text.replace("\n[peg]\ndiameter_m = 0.010 ", f"\n[peg]\ndiameter_m = {diameter} ", 1))
    return path


def sim(world: Path, *board: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--quiet", "--duration", "0.2",
                           "--no-c28x-check", "--world", str(world), *board], capture_output=True, text=True,
                          timeout=300, env=os.environ)


@pytest.mark.parametrize("board", [[], ["--native"]], ids=["wasm", "native"])
def test_a_world_mujoco_refuses_is_blamed_on_its_file(tmp_path, board):
    world = world_with_peg_diameter(tmp_path, "1e-9")
    load_world(world)  # every value within its range: only MuJoCo can tell
    r = sim(world, *board)
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().splitlines() == [
        f"crslab sim: {world}: MuJoCo refuses the world it describes: inertia must have positive eigenvalues "
        "(the peg)"]


def test_the_same_world_with_a_peg_mujoco_accepts_runs(tmp_path):
    r = sim(world_with_peg_diameter(tmp_path, "1e-4"))
    assert r.returncode == 0, r.stderr
