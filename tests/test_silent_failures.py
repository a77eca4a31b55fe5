"""Failures that used to be silent are named: a lab that triggers printing but defines no
printing() (it prints nothing and exits 0), and a sweep whose runs trip before the lab runs."""

import subprocess
import sys
from pathlib import Path

import pytest

LABS = Path(__file__).parent / "labs"


def crslab(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=300, cwd=cwd)


@pytest.mark.parametrize("lab, how, near", [("printing_typo_gen_a.c", "SWI_post(&SWI_printf)", "Printing"),
                                            ("printng_typo_gen_b.c", "UARTprint = 1", "printng")])
@pytest.mark.parametrize("command", ["sim", "record"])
def test_a_lab_that_triggers_printing_without_printing_is_warned_with_the_near_name(tmp_path, lab, how, near,
                                                                                    command):
    args = ["--fast", "--quiet", "--no-stdin"] if command == "sim" else ["-o", tmp_path / "g.txt"]
    r = crslab(command, "--lab", LABS / lab, "--duration", "6", *args)
    assert r.returncode == 0 and r.stdout == ""  # as on the board: nothing printed, no error
    # printing is triggered every 500 calls from 4.1 s: at 4.1, 4.6, 5.1 and 5.6 s
    assert (f"crslab {command}: warning: {lab} triggered printing 4 times ({how}) but defines no printing(), "
            f"so nothing was printed, as on the board; did you mean {near}() to be printing()?") in r.stderr


def test_a_lab_with_printing_gets_no_such_warning(tmp_path):
    r = crslab("sim", "--lab", LABS / "lab1_own_ik.c", "--fast", "--quiet", "--no-stdin", "--duration", "6")
    assert r.returncode == 0 and r.stdout.count("\n") == 12
    assert "printing()" not in r.stderr


def test_a_sweep_says_when_its_runs_tripped_before_the_lab_could_act(tmp_path):
    """A payload the hold controller cannot hold takes the arm out of the envelope before 4.1 s, so
    the lab's first call already finds it outside: every such run fails, whatever the lab does."""
    r = crslab("sweep", "--vary", "payload_kg=0:2", "--grid", "2", "--duration", "4.2", "--jobs", "1",
               "-o", tmp_path / "s.csv")
    assert r.returncode == 1, r.stderr  # a run failed
    rows = [line.split(",") for line in (tmp_path / "s.csv").read_text().splitlines()]
    col = rows[0].index("trips_before_lab")
    assert [row[col] for row in rows[1:]] == ["0", "1"]  # no payload: none; 2 kg: one, at the first call
    assert "note: in 1 of 2 runs the arm left the safety envelope or the motor board cut out by lab()'s " \
           "first call" in r.stdout + r.stderr
    r = crslab("sweep", "--vary", "friction=1.0:1.2", "--grid", "2", "--duration", "4.2", "--jobs", "1",
               "-o", tmp_path / "no_payload.csv")
    assert r.returncode == 0 and "note: in" not in r.stdout + r.stderr
