"""``crslab new``: a starting file for each lab in each generation, that compiles unmodified,
is found to be of its generation, runs, and does what its comment says on the simulated arm."""

import math
import subprocess
import sys

import pytest

from crslab.generations import detect
from crslab.run.api import simulate
from crslab.starters import LABS, starter_text

GEN = {"A": 1, "B": 2}
REST_DEG = (-24.06, 13.75)  # hands_off's resting pose (motor angles 2 and 3): -0.42, 0.24 rad
OFFSETS_DEG = (math.degrees(-0.37), math.degrees(0.27))  # the starters' offsets (the template's)


def crslab(*args, cwd):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=120, cwd=cwd)


def numbers(line):
    return [float(w) for w in line.replace("error", " ").split()]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Every starter written by the command as a student types it, then run 7.6 s on hands_off."""
    folder = tmp_path_factory.mktemp("new")
    out = {}
    for lab in LABS:
        for gen in GEN:
            name = f"{lab}_{gen}.c"
            r = crslab("new", lab, "--gen", gen, name, cwd=folder)
            assert r.returncode == 0, r.stderr
            hint = {"lab4": f"crslab sim --lab {name} --scenario lab4_push",
                    "final": f"crslab contest --lab {name}"}.get(lab, f"crslab sim --lab {name}")
            assert f"run it with '{hint}'" in r.stderr
            text = (folder / name).read_text()
            out[lab, gen] = text, simulate(folder / name, "hands_off", duration_s=7.6)
    return out


@pytest.mark.parametrize("lab", list(LABS))
@pytest.mark.parametrize("gen", list(GEN))
def test_each_starter_is_of_its_generation_and_runs_to_the_end(runs, lab, gen):
    text, run = runs[lab, gen]
    assert detect(text).id == GEN[gen]
    assert ("SWI_post(&SWI_printf);" in text) == (gen == "A") and ("UARTprint = 1;" in text) == (gen == "B")
    assert run.status == "ok" and run.end_tick == 7600, run.message
    assert run.stats.lab_calls == 3500 and run.stats.motor_board_cutouts == 0
    assert run.lines(), "it prints"


@pytest.mark.parametrize("gen", list(GEN))
def test_lab1_prints_its_offsets_at_rest_and_zero_until_the_todos_are_written(runs, gen):
    _, run = runs["lab1", gen]
    first = run.lines()[:3]
    # each printed angle is the true angle minus the resting angle plus the file's offset
    assert numbers(first[0]) == pytest.approx([0.0, *OFFSETS_DEG], abs=0.02)
    assert first[1:] == ["0.00 0.00 0.00"] * 2


@pytest.mark.parametrize("gen", list(GEN))
@pytest.mark.parametrize("lab", ["lab2", "lab3"])
def test_lab2_and_lab3_settle_on_their_reference_within_15_mrad(runs, lab, gen):
    _, run = runs[lab, gen]
    rows = [numbers(line) for line in run.lines()]  # every 100 ms: the reference, then motor 1..3
    # where the reference has held still for 0.5 s, each joint is on it
    held = [row for i, row in enumerate(rows) if i >= 5 and all(r[0] == row[0] for r in rows[i - 5:i])]
    references = {r[0] for r in held}  # lab2: 0 and pi/6 (Gen A's printf truncates it to 0.523)
    assert len(held) >= 5
    assert (any(abs(r - math.pi / 6) < 0.002 for r in references) and 0.0 in references) if lab == "lab2" \
        else 0.5 in references
    for row in held:
        assert row[1:] == pytest.approx([row[0]] * 3, abs=0.015), row  # gravity: a small offset


@pytest.mark.parametrize("gen", list(GEN))
def test_lab4_holds_the_hand_where_it_started(runs, gen):
    _, run = runs["lab4", gen]
    rows = [numbers(line) for line in run.lines()]
    # the resting pose as the lab measures it (its offsets, the simulated arm's rest: motor angles 0,
    # -0.42, 0.24 rad: the course's forward kinematics, 10 in links, x = 10 (cos q3 + sin q2)), held
    rest = [10 * (math.cos(0.24) + math.sin(-0.42)), 0.0, 10 * (1 + math.cos(-0.42) - math.sin(0.24))]
    for row in rows:
        assert row[:3] == pytest.approx(rest, abs=0.06) and max(map(abs, row[3:])) <= 0.05, row


def test_new_keeps_an_existing_file_and_writes_where_it_is_told(tmp_path):
    (tmp_path / "lab1.c").write_text("mine")
    r = crslab("new", "lab1", cwd=tmp_path)
    assert r.returncode == 2 and "lab1.c: exists; not replacing it (--force overwrites it)" in r.stderr
    assert (tmp_path / "lab1.c").read_text() == "mine"
    assert crslab("new", "lab1", "--force", cwd=tmp_path).returncode == 0
    assert (tmp_path / "lab1.c").read_text() == starter_text("lab1", "B")
    assert crslab("new", "lab3", "--gen", "A", "-o", "labs/three.c", cwd=tmp_path).returncode == 0
    assert (tmp_path / "labs" / "three.c").read_text() == starter_text("lab3", "A")
    r = crslab("new", "lab2", "notes.txt", cwd=tmp_path)
    assert r.returncode == 2 and "a lab file is a .c file" in r.stderr


@pytest.mark.parametrize("gen", list(GEN))
def test_lab4_and_final_rest_where_the_simulated_arm_rests_and_say_how_to_run_them(gen):
    from crslab.contest.offsets import lab_offsets
    from crslab.plant.model_files import REST_MOTOR_RAD

    for lab in ("lab4", "final"):
        text = starter_text(lab, gen)
        assert lab_offsets(text).rad == pytest.approx(REST_MOTOR_RAD[1:], abs=1e-7)
    assert "crslab sim --lab lab4.c --scenario lab4_push" in starter_text("lab4", gen)


def test_crslab_help_lists_new_final(tmp_path):
    r = crslab("--help", cwd=tmp_path)
    [line] = [x for x in r.stdout.splitlines() if x.split()[:1] == ["new"]]
    assert "lab1..lab4, final" in line
