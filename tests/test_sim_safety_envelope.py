"""Lab 4's sign error is not silent: with a negative z gain the course's Lab 4 controller pushes the
arm away from its point, out of the framework's safety envelope, and the framework's hold controller
takes over the torques (docs/framework.md section 4). The end-of-run summary names the trip, its
tick and the hold taking over, as the CSV's ``safety`` column shows it."""

from __future__ import annotations

import csv
import re
import subprocess
import sys
from pathlib import Path

import pytest

from crslab.framework_facts import STARTUP_TICKS


def lab4(folder: Path, kpz: str) -> Path:
    """crslab's Lab 4 starting file with the z gain ``kpz``."""
    path = folder / "lab4.c"
    subprocess.run([sys.executable, "-m", "crslab", "new", "lab4", str(path)], check=True,
                   capture_output=True)
    text = path.read_text()
    assert "float KPz = 0.5;" in text
    path.write_text(text.replace("float KPz = 0.5;", f"float KPz = {kpz};"))
    return path


def run(lab: Path, out: Path) -> tuple[str, list[int]]:
    """``crslab sim`` of ``lab`` on the course's Lab 4 push: its stderr and the CSV's safety flags."""
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--scenario", "lab4_push",
                        "--fast", "--quiet", "--duration", "15", "--csv", str(out)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    with out.open() as f:
        rows = list(csv.DictReader(f))
    return r.stderr, [int(row["safety [0/1]"]) for row in rows]


@pytest.fixture(scope="module")
def sign_error(tmp_path_factory):
    folder = tmp_path_factory.mktemp("lab4-sign-error")
    return run(lab4(folder, "-0.5"), folder / "run.csv")


def test_the_summary_names_the_trip_its_tick_and_the_hold_taking_over(sign_error):
    stderr, safety = sign_error
    first = safety.index(1)
    trips = sum(1 for before, now in zip([0, *safety], safety) if now and not before)
    assert first >= STARTUP_TICKS  # the envelope is the lab's: checked from its first call on
    said = re.search(r"the arm left the safety envelope at tick (\d+) \(t = (\d+\.\d{3}) s\): the "
                     r"framework's hold took over from lab\(\) \((once|\d+ times), ([\d,]+) ticks in all\)",
                     stderr)
    assert said, stderr
    assert int(said.group(1)) == first and float(said.group(2)) == first / 1000
    assert said.group(3) == ("once" if trips == 1 else f"{trips} times")
    assert int(said.group(4).replace(",", "")) == sum(safety)


def test_lab4_as_written_stays_inside_and_says_nothing_of_the_envelope(tmp_path):
    stderr, safety = run(lab4(tmp_path, "0.5"), tmp_path / "run.csv")
    assert sum(safety) == 0 and "safety envelope" not in stderr
