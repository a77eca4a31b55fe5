"""The budget has one owner (crslab/run/budget.py): the board counts lab()'s calls over it and says
the budget it counted against in the run's counters (``RunStats.budget``), and every command that
accepts ``--budget`` reports what it counted from there: ``sim`` (its summary), ``record`` and
``check`` and ``contest`` (one line each, after what they print), ``grade`` (two columns of
grades.csv), ``sweep`` (a column). A command that takes ``--budget`` and says nothing of it fails
here."""

from __future__ import annotations

import argparse
import csv
import importlib
import json
import subprocess
import sys
from pathlib import Path

from crslab.cli import COMMANDS

LABS = Path(__file__).resolve().parent / "labs"
BUSY = LABS / "faulty" / "busy_lab.c"
"""Every lab() call costs the same count of instructions, well over 200,000 (100,000 rounds of a
multiply-add)."""
RUN = ["--scenario", "hands_off", "--no-startup-delay", "--duration", "0.005", "--budget", "200000"]
REPORTED = {"sim", "record", "check", "grade", "sweep", "debug", "contest"}
"""The commands that accept --budget (debug reports it as sim does, with the same summary: it needs
gdb, so it is not run here)."""


def crslab(*args: object, cwd: Path | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=300, cwd=cwd)


def test_every_command_that_accepts_budget_is_one_this_test_knows():
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers(dest="command")
    for module_name in COMMANDS:
        importlib.import_module(module_name).register(sub)
    taking = {name for name, p in sub.choices.items()
              if any("--budget" in action.option_strings for action in p._actions)}
    assert taking == REPORTED


def test_sim_record_check_contest_grade_and_sweep_each_report_the_calls_over_the_budget(tmp_path):
    sim = crslab("sim", "--fast", "--quiet", "--lab", BUSY, *RUN, "--json")
    assert sim.returncode == 0, sim.stderr
    info = json.loads(sim.stderr.strip().splitlines()[-1])
    assert (info["budget"], info["lab_calls"], info["over_budget"]) == (200_000, 5, 5)
    said = "5 over the budget of 200,000 instructions (ticks 0, 1, 2, 3, 4)"

    golden = tmp_path / "busy.txt"
    record = crslab("record", "--lab", BUSY, *RUN, "-o", golden)
    assert record.returncode == 0 and record.stderr.strip().splitlines()[-1].endswith(said), record.stderr
    check = crslab("check", "--lab", BUSY, "--golden", golden, "--budget", "200000")
    assert check.returncode == 0 and "crslab check: lab() x5: " in check.stderr and said in check.stderr

    contest = crslab("contest", "--lab", BUSY, *RUN)
    assert contest.returncode == 1 and contest.stderr.strip().splitlines()[-1].endswith(said), contest.stderr

    (tmp_path / "class").mkdir()
    (tmp_path / "class" / "busy.c").write_bytes(BUSY.read_bytes())
    grade = crslab("grade", tmp_path / "class", "--reference", BUSY, *RUN, "-o", tmp_path / "grades")
    assert grade.returncode == 0, grade.stderr
    with (tmp_path / "grades" / "grades.csv").open() as f:
        (row,) = list(csv.DictReader(f))
    assert (row["over_budget"], row["budget"]) == ("5", "200000")

    sweep = crslab("sweep", "--lab", BUSY, *RUN, "--vary", "friction=0.9:1.1", "--samples", "1",
                   "-o", tmp_path / "sweep.csv")
    assert sweep.returncode in (0, 1), sweep.stderr
    with (tmp_path / "sweep.csv").open() as f:
        (sample,) = list(csv.DictReader(f))
    assert sample["over_budget"] == "5"
