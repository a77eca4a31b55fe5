"""Scenario expectations (``kind = "expect"``): each condition met and failed on a lab whose
behaviour is known, the run's status and exit status, the reports of sim, record, check and grade,
a transcript that expectations never change, and malformed expectations as one-line errors."""

import csv
import dataclasses
import json
import math
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from crslab.lab.build import build_lab
from crslab.pytest_plugin import CrslabCheckFailed, check_against_golden
from crslab.regress.grade import grade_result
from crslab.run.api import simulate
from crslab.run.status import ExitStatus, GradeClass, RunResult, RunStatus
from crslab.scenario.expect_events import Angles, BoardOff, Expect, Judge, Observation
from crslab.scenario.load import BUILTIN_DIR, ScenarioError, check_lab, load_scenario, parse_scenario

LABS = Path(__file__).parent / "labs"
SATURATING = LABS / "saturating_gen_b.c"  # +-4.5 on joint 1 from 4.1 s: the board cuts out at tick 4600
OPEN_LOOP = LABS / "open_loop_tau1.c"     # *tau1 = 1: leaves the envelope during tick 4959
TORQUE_SIGNS = LABS / "torque_signs.c"    # drives joint `torquejoint` with `torqueunits` (1.0)
SIGN_MESSAGE = "a positive torque on joint 1 must make its motor angle grow: check the sign of tau1"

# The motor board (Gen B's Piccolo): the lab first commands beyond 4 units at tick 4100, so the
# board cuts every output during tick 4600 and brings them back during tick 6100, when the lab
# commands 0. An expectation at tick k sees the board as tick k - 1 left it.
CUT = """\
name = "cut"
end = 6.2

[[event]]
at = 4.6
kind = "expect"
motor_board_off = true
message = "the board is still on before tick 4600 runs"

[[event]]
at = 4.6
kind = "expect"
motor_board_off = false
motor_board_cutouts = 0

[[event]]
at = 4.601
kind = "expect"
motor_board_off = true
motor_board_cutouts = 1

[[event]]
at = 6.1
kind = "expect"
motor_board_off = true

[[event]]
at = 6.101
kind = "expect"
motor_board_off = false
motor_board_cutouts = 1

[[event]]
at = 4.0
kind = "expect"
motor_rad = [0, -0.42, 0.24]
tol_rad = 0.001

[[event]]
at = 4.0
kind = "expect"
joint = 2
motor_deg = -20
"""


def crslab(*args, timeout=180):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout)


def parse(text, name="x.toml"):
    return parse_scenario(text, Path(name))


def outcome_at(run, where):
    [found] = [e for e in run.expectations if e.where == where]
    return found


@pytest.fixture(scope="module")
def cut(tmp_path_factory):
    path = tmp_path_factory.mktemp("scenarios") / "cut.toml"
    path.write_text(CUT)
    return simulate(SATURATING, str(path), log=True)


def test_the_motor_board_is_expected_off_from_the_tick_after_the_cutout(cut):
    # the scope log, a second witness: off from tick 4600 (during it) to 6099
    off = cut.log["motor_board_off"][:, 0]
    assert off[4599] == 0 and off[4600] == 1 and off[6099] == 1 and off[6100] == 0
    before = outcome_at(cut, "cut.toml:6")
    assert not before.met and before.failures == ("expected the motor board off, it was on",)
    assert before.lines() == ["t = 4.600 s: expected the motor board off, it was on (cut.toml:6): the board "
                              "is still on before tick 4600 runs"]
    assert outcome_at(cut, "cut.toml:12").met              # on, no cut-out yet, at 4.600
    assert outcome_at(cut, "cut.toml:18").met              # off and one cut-out at 4.601
    assert outcome_at(cut, "cut.toml:24").met              # still off at 6.100 (back during tick 6100)
    assert outcome_at(cut, "cut.toml:29").met              # back on at 6.101


def test_motor_angles_are_the_arms_now_within_the_tolerance(cut):
    at_rest = outcome_at(cut, "cut.toml:35")
    assert at_rest.met, at_rest.failures
    wrong = outcome_at(cut, "cut.toml:41")
    # the arm rests at joint 2 = -0.42 rad = -24.06 deg: 4.06 deg from -20, more than 1 deg
    assert wrong.failures == ("expected joint 2 motor angle -20.00 deg within 1 deg, it was -24.06 deg "
                              "(off by 4.06 deg)",)


def test_a_failed_expectation_ends_the_run_unmet_with_exit_status_1(cut):
    assert cut.status is RunStatus.UNMET and cut.exit_status == ExitStatus.MISMATCH == 1
    assert cut.end_tick == 6200 and not cut.ok
    assert cut.message == "2 of 7 expectations of scenario cut failed"
    assert [e.tick for e in cut.expectations] == [4000, 4000, 4600, 4600, 4601, 6100, 6101]
    assert [e.where for e in cut.failed_expectations] == ["cut.toml:41", "cut.toml:6"]
    assert cut.diagnosis().splitlines()[1:] == [line for e in cut.failed_expectations for line in e.lines()]


def test_expectations_never_change_the_transcript(cut, tmp_path):
    plain = tmp_path / "plain.toml"
    plain.write_text('name = "plain"\nend = 6.2\n')
    without = simulate(SATURATING, str(plain))
    assert without.status is RunStatus.OK and without.expectations == []
    assert cut.transcript == without.transcript and cut.calls == without.calls and cut.sent == without.sent
    assert len(cut.calls) == 2  # "call 0", "call 2000": something to compare


def test_the_error_flag_is_what_lab_gets_at_that_tick(tmp_path):
    path = tmp_path / "envelope.toml"
    path.write_text('end = 5.2\n'
                    '[[event]]\nat = 5.058\nkind = "expect"\nerror = 0\n'
                    '[[event]]\nat = 5.058\nkind = "expect"\nerror = 1\n'
                    '[[event]]\nat = 5.059\nkind = "expect"\nerror = 1\n')
    run = simulate(OPEN_LOOP, str(path))
    # the lab prints the flag when it changes: it got error = 1 first at tick 5059
    assert run.calls[0][0] == 5059 and run.calls[0][1].startswith(b"error 1 at ")
    assert [e.met for e in run.expectations] == [True, False, True]
    assert run.expectations[1].failures == (
        "expected error = 1 (the arm outside the safety envelope), it was 0",)


@pytest.fixture(scope="module")
def torque_signs():
    return simulate(TORQUE_SIGNS, "lab1_torque_signs")


def test_lab1_torque_signs_expects_each_driven_joint_to_rise(torque_signs):
    assert torque_signs.status is RunStatus.OK
    assert [(e.tick, e.what, e.met) for e in torque_signs.expectations] == [
        (5500, "joint 1 motor angle up by at least 1 deg since 5 s", True),
        (8500, "joint 2 motor angle up by at least 1 deg since 8 s", True),
        (11500, "joint 3 motor angle up by at least 1 deg since 11 s", True)]


def test_the_builtin_expectations_change_nothing_a_lab_prints(torque_signs):
    scenario = load_scenario("lab1_torque_signs")
    kept = tuple(e for e in scenario.events if not isinstance(e, Expect))
    bare = dataclasses.replace(scenario, events=kept)
    assert len(bare.events) == len(scenario.events) - 6  # three expectations, three notes of angles
    without = simulate(TORQUE_SIGNS, bare)
    assert without.expectations == [] and without.transcript == torque_signs.transcript


def reversed_torque_signs(folder: Path) -> Path:
    """lab1_torque_signs with the lab's torque turned negative: every joint falls."""
    path = folder / "reversed.toml"
    text = (BUILTIN_DIR / "lab1_torque_signs.toml").read_text()
    path.write_text(text.replace("end = 14.0\n", 'end = 14.0\n\n[[event]]\nat = 4.5\nkind = "set"\n'
                                 'var = "torqueunits"\nvalue = -1.0\n'))
    return path


def test_a_watched_variable_and_a_fall_are_checked(tmp_path):
    path = reversed_torque_signs(tmp_path)
    path.write_text(path.read_text() + (
        '\n[[event]]\nat = 5.2\nkind = "expect"\nvar = "torquejoint"\nvalue = 1\n'
        '\n[[event]]\nat = 5.2\nkind = "expect"\nvar = "torquejoint"\nvalue = 2\n'
        '\n[[event]]\nat = 5.2\nkind = "expect"\nvar = "torqueunits"\nvalue = -0.9\ntol = 0.1\n'
        '\n[[event]]\nat = 5.5\nkind = "expect"\njoint = 1\nmoved_deg = -1\nsince = 5.0\n'))
    run = simulate(TORQUE_SIGNS, str(path), log=True, duration_s=9.0)
    by_what = {e.what: e for e in run.expectations}
    assert by_what["torquejoint = 1"].met and by_what["torqueunits = -0.9 within 0.1"].met
    assert by_what["torquejoint = 2"].failures == ("expected torquejoint = 2, it was 1",)
    fell = by_what["joint 1 motor angle down by at least 1 deg since 5 s"]
    assert fell.met
    rose = by_what["joint 1 motor angle up by at least 1 deg since 5 s"]
    # how far joint 1 moved, from the scope log: the plant's angle at ticks 5500 and 5000
    moved = math.degrees(run.log["qpos_dh_rad"][5500, 0] - run.log["qpos_dh_rad"][5000, 0])
    assert moved < -1.0
    assert rose.failures == (f"expected joint 1 motor angle up by at least 1 deg since 5 s, it moved by "
                             f"{moved:.2f} deg",)
    assert rose.message == SIGN_MESSAGE
    assert not by_what["joint 2 motor angle up by at least 1 deg since 8 s"].met
    assert not by_what["joint 3 motor angle up by at least 1 deg since 11 s"].reached  # after the end (9 s)
    assert run.status is RunStatus.UNMET
    assert run.message == "3 of 7 expectations of scenario lab1_torque_signs failed"


def observed(**changes):
    seen = dict(tick=1000, motor_board="piccolo", motor_board_off=False, motor_board_cutouts=0, error=0,
                motor_rad=(0.0, 0.0, 0.0))
    seen.update(changes)
    return Observation(**seen)


def test_dh_angles_are_the_arms_motor_angles_in_dh():
    # motor zero is DH (0, -90, 90) deg (the tour's first pose)
    dh = Angles("DH", tuple(np.radians([0, -90, 90])), (1, 2, 3), math.radians(0.01), "deg")
    assert dh.failure(observed(), {}) is None
    bent = observed(motor_rad=(0.0, math.radians(2), 0.0))
    # DH 2 = motor 2 - 90 deg, DH 3 = motor 3 - motor 2 + 90 deg: both off by 2 deg; the first is named
    assert dh.failure(bent, {}) == ("expected DH angles (0.00, -90.00, 90.00) deg within 0.01 deg, they were "
                                    "(0.00, -88.00, 88.00) deg (joint 2 off by 2.00 deg)")
    in_rad = Angles("motor", (0.5,), (3,), 0.01, "rad")
    assert in_rad.failure(observed(motor_rad=(0.0, 0.0, 0.505)), {}) is None
    assert in_rad.failure(observed(motor_rad=(0.0, 0.0, 0.52)), {}) == (
        "expected joint 3 motor angle 0.5000 rad within 0.01 rad, it was 0.5200 rad (off by 0.0200 rad)")


def test_a_run_without_a_motor_board_says_so_when_it_was_expected_off():
    assert BoardOff(True).failure(observed(motor_board="none"), {}) == (
        "expected the motor board off, it was on (this run has no motor board: --motor-board none)")


def test_the_judge_refuses_observations_nobody_asked_for():
    s = parse('end = 9\n[[event]]\nat = 5\nkind = "expect"\nerror = 0\n')
    judge = Judge(s.events, "x.toml")
    with pytest.raises(ValueError, match="at tick 4000 that no expectation asked for"):
        judge.observed(observed(tick=4000))
    assert judge.observed(observed(tick=5000)).met
    with pytest.raises(ValueError):
        judge.observed(observed(tick=5000))


def test_grading_classes_a_failed_expectation_unmet_whatever_the_transcript(cut):
    reference = dataclasses.replace(cut, status=RunStatus.OK, expectations=[])
    same = dataclasses.replace(cut, lab_file=Path("same.c"))
    grade = grade_result(same, reference)
    assert grade.grade is GradeClass.UNMET
    assert grade.detail == ("2 of 7 expectations failed; first at t = 4.000 s: expected joint 2 motor angle "
                            "-20.00 deg within 1 deg, it was -24.06 deg (off by 4.06 deg) (cut.toml:41); "
                            "2 lines match")
    assert grade.report.splitlines() == cut.diagnosis().splitlines()
    ok = grade_result(dataclasses.replace(reference, lab_file=Path("ok.c")), reference)
    assert ok.grade is GradeClass.PASS
    crashed = dataclasses.replace(cut, status=RunStatus.CRASHED, message="same.c crashed (SIGSEGV)")
    assert grade_result(crashed, reference).grade is GradeClass.CRASHED
    assert "expected joint 2 motor angle" in grade_result(crashed, reference).report


def test_crslab_sim_announces_reports_and_exits_1(tmp_path):
    path = reversed_torque_signs(tmp_path)
    r = crslab("sim", "--fast", "--lab", TORQUE_SIGNS, "--scenario", path, "--duration", "9", "--no-stdin",
               "--json")
    assert r.returncode == 1, r.stderr
    lines = r.stderr.splitlines()
    failure = ("expected joint 1 motor angle up by at least 1 deg since 5 s, it moved by -")
    assert any(line.startswith(f"crslab sim: t = 5.5 s: expectation failed: {failure}") for line in lines)
    assert "crslab sim: t = 5.0 s: expect: note the motor angles (for the expectation at 5.5 s)" in lines
    at_end = [line for line in lines if line.startswith("crslab sim: expectation failed: ")]
    assert len(at_end) == 2
    assert at_end[0].startswith(f"crslab sim: expectation failed: t = 5.500 s: {failure}")
    assert at_end[0].endswith(f"(reversed.toml:30): {SIGN_MESSAGE}")
    info = json.loads(next(line for line in lines if line.startswith("{")))
    assert (info["status"], info["expectations_met"], info["expectations_failed"],
            info["expectations_not_reached"]) == ("unmet", 0, 2, 1)
    assert [e["met"] for e in info["expectations"]] == [False, False, None]
    assert info["expectations"][0]["where"] == "reversed.toml:30"
    assert lines[-1] == "crslab sim: 2 of 3 expectations of scenario lab1_torque_signs failed"
    assert r.stdout.startswith("joint 0: ")  # what the lab printed, untouched

    quiet = crslab("sim", "--fast", "--lab", TORQUE_SIGNS, "--scenario", "lab1_torque_signs", "--no-stdin",
                   "--quiet")
    assert quiet.returncode == 0, quiet.stderr
    assert "expect" not in quiet.stderr.replace("expectations: 3 met", "")
    assert quiet.stderr.splitlines()[-1].endswith("; expectations: 3 met")


def test_record_refuses_and_check_fails_on_a_failed_expectation(tmp_path):
    path = reversed_torque_signs(tmp_path)
    golden = tmp_path / "golden.txt"
    r = crslab("record", "--lab", TORQUE_SIGNS, "--scenario", path, "--duration", "6", "-o", golden)
    assert r.returncode == 1 and not golden.exists()
    lines = r.stderr.splitlines()
    assert lines[0].startswith("crslab record: expectation failed: t = 5.500 s: expected joint 1 motor angle")
    assert lines[-1] == ("crslab record: 1 of 3 expectations of scenario lab1_torque_signs failed; "
                         "nothing was written")

    r = crslab("record", "--lab", TORQUE_SIGNS, "--scenario", "lab1_torque_signs", "--duration", "6", "-o",
               golden)
    assert r.returncode == 0 and golden.exists(), r.stderr
    junit = tmp_path / "check.xml"
    r = crslab("check", "--lab", TORQUE_SIGNS, "--golden", golden, "--scenario", path, "--junit", junit)
    assert r.returncode == 1, r.stderr
    report = r.stdout.splitlines()
    assert report[0] == "1 of 3 expectations of scenario lab1_torque_signs failed"
    assert report[1].startswith("t = 5.500 s: expected joint 1 motor angle up by at least 1 deg since 5 s")
    assert report[2].startswith("mismatch: ")  # the reversed torque printed other angles too
    [failure] = ET.parse(junit).getroot().iter("failure")
    assert failure.get("message") == report[0] and report[1] in failure.text


def test_the_pytest_fixture_fails_and_records_nothing(tmp_path):
    path = reversed_torque_signs(tmp_path)
    with pytest.raises(CrslabCheckFailed, match=r"t = 5\.500 s: expected joint 1 motor angle up") as err:
        check_against_golden(TORQUE_SIGNS, golden=tmp_path / "g.txt", scenario=str(path), base=tmp_path,
                             record=True, duration_s=6.0)
    assert "1 of 3 expectations" in str(err.value) and not (tmp_path / "g.txt").exists()


def test_grade_classes_a_wrong_sign_unmet_and_refuses_a_reference_that_fails(tmp_path):
    subs = tmp_path / "submissions"
    subs.mkdir()
    shutil.copy(TORQUE_SIGNS, subs / "good.c")
    text = TORQUE_SIGNS.read_text()
    assert text.count("? torqueunits : 0") == 3
    (subs / "wrong.c").write_text(text.replace("? torqueunits : 0", "? -torqueunits : 0"))
    out = tmp_path / "grades"
    r = crslab("grade", subs, "--reference", TORQUE_SIGNS, "--scenario", "lab1_torque_signs", "--duration",
               "12", "--out", out)
    assert r.returncode == 1, r.stderr
    rows = {line.split()[0]: line for line in r.stdout.splitlines()[1:-1]}
    assert rows["good.c"].split()[1] == "pass"
    assert rows["wrong.c"].split()[1] == "unmet"
    assert "3 of 3 expectations failed; first at t = 5.500 s: expected joint 1 motor" in rows["wrong.c"]
    assert r.stdout.splitlines()[-1] == (
        "2 submissions: 1 pass, 0 mismatch, 1 unmet, 0 does not compile, 0 crashed, 0 hung")
    with (out / "grades.csv").open() as f:
        graded = {row["submission"]: row for row in csv.DictReader(f)}
    assert (graded["good.c"]["expectations_failed"], graded["wrong.c"]["expectations_failed"]) == ("0", "3")
    assert graded["wrong.c"]["result"] == "unmet"
    cases = {c.get("name"): c for c in ET.parse(out / "junit.xml").getroot().iter("testcase")}
    [failure] = cases["wrong.c"].iter("failure")
    assert failure.get("message").startswith("unmet: 3 of 3 expectations failed")
    for t in ("5.500", "8.500", "11.500"):
        assert f"t = {t} s: expected joint" in failure.text
    assert "lines differ" in failure.text  # and the transcript differs as well
    assert "t = 8.500 s: expected joint 2" in (out / "reports" / "wrong.c.txt").read_text()

    r = crslab("grade", subs, "--reference", subs / "wrong.c", "--scenario", "lab1_torque_signs",
               "--duration", "6", "--out", tmp_path / "again")
    assert r.returncode == 2
    moved = r.stderr.split("it moved by ")[1].split(" deg")[0]
    assert float(moved) < -1.0
    assert r.stderr.strip().splitlines()[-1] == (
        "crslab grade: the reference lab wrong.c does not meet the scenario's expectations: 1 of 3 "
        "expectations of scenario lab1_torque_signs failed; the first: t = 5.500 s: expected joint 1 motor "
        f"angle up by at least 1 deg since 5 s, it moved by {moved} deg (lab1_torque_signs.toml:24): "
        f"{SIGN_MESSAGE}")


def test_crslab_scenarios_prints_expectations_in_the_timeline(tmp_path):
    path = tmp_path / "cut.toml"
    path.write_text(CUT)
    r = crslab("scenarios", path)
    assert r.returncode == 0, r.stderr
    assert "   4.601 s  expect the motor board off, 1 motor-board cut-out so far  (line 18)" in r.stdout
    assert ("   4.000 s  expect motor angles (0.0000, -0.4200, 0.2400) rad within 0.001 rad  (line 35)"
            in r.stdout)
    r = crslab("scenarios", "lab1_torque_signs")
    assert "   5.500 s  expect joint 1 motor angle up by at least 1 deg since 5 s  (line 24)" in r.stdout


@pytest.mark.parametrize("body, error", [
    ("motor_board_off = 1\n", "x.toml:5: motor_board_off: must be true or false, got 1"),
    ("error = 2\n", "x.toml:5: error: must be from 0 to 1, got 2"),
    ("motor_board_cutouts = -1\n", "x.toml:5: motor_board_cutouts: must be from 0 to 2147483647, got -1"),
    ('message = "nothing"\n', "x.toml:4: kind: an expectation needs a condition (one or more of: "
     "motor_board_off, motor_board_cutouts, error, motor_deg, motor_rad, dh_deg, moved_deg, var, egg_force, "
     "scale_g, peg_depth, egg_broken, contact)"),
    ("scale_g = 500\n", "x.toml:5: scale_g: must be a range [low, high], got 500"),
    ("contact.egs = true\n",
     "x.toml:5: contact.egs: no fixture 'egs' (fixtures: table, hole, obstacle, groove, egg)"),
    ("egg_broken = 1\n", "x.toml:5: egg_broken: must be true or false, got 1"),
    ("motor_deg = [1, 2]\n", "x.toml:5: motor_deg: must be a list of three numbers, got [1, 2]"),
    ("motor_deg = 5\n", "x.toml:5: motor_deg: must be a list of three numbers, or one number with joint or "
     "joints, got 5"),
    ("motor_deg = [0, 0, 0]\njoint = 2\n", "x.toml:5: motor_deg: a list gives every joint its value: leave "
     "out joint/joints"),
    ("motor_deg = [0, 0, 0]\ndh_deg = [0, 0, 0]\n", "x.toml:6: dh_deg: give one of motor_deg, motor_rad, "
     "dh_deg, not several"),
    ("error = 0\ntol_deg = 1\n", "x.toml:6: tol_deg: only with motor_deg, motor_rad, dh_deg"),
    ("motor_rad = [0, 0, 0]\ntol_deg = 1\ntol_rad = 0.1\n", "x.toml:7: tol_rad: give tol_deg or tol_rad"),
    ("motor_rad = [0, 0, 0]\ntol_rad = -1\n", "x.toml:6: tol_rad: must be at least 0, got -1"),
    ("moved_deg = 2\n", "x.toml:2: since: missing (moved_deg counts from the motor angles at this time"),
    ("moved_deg = 2\nsince = 6\n", "x.toml:6: since: must be earlier than at"),
    ("moved_deg = 0\nsince = 1\n", "x.toml:5: moved_deg: must not be 0: its sign says which way"),
    ("moved_deg = [1, 1, 1]\nsince = 1\n", "x.toml:5: moved_deg: must be one number of degrees"),
    ("error = 0\nsince = 1\n", "x.toml:6: since: only with moved_deg"),
    ("error = 0\njoint = 1\n", "x.toml:6: joint: only with moved_deg, or one number of motor_deg"),
    ("motor_deg = [0, 0, 0]\nmoved_deg = 1\nsince = 1\njoint = 1\n", "x.toml:5: motor_deg: a list gives "
     "every joint its value: leave out joint/joints (to choose the joints of moved_deg, give it an "
     "expectation of its own)"),
    ("error = 0\nvalue = 1\n", "x.toml:6: value: only with var"),
    ('var = "1x"\nvalue = 1\n', "x.toml:5: var: must be a C variable name, got '1x'"),
    ('var = "Kp"\n', "x.toml:2: value: missing"),
    ('var = "Kp"\nvalue = 1\ntol = -1\n', "x.toml:7: tol: must be at least 0, got -1"),
    ("error = 0\nmessage = 3\n", "x.toml:6: message: must be a string, got 3"),
    ("error = 0\nwithin = 3\n", "x.toml:6: within: unknown key (allowed: "),
])
def test_a_malformed_expectation_is_one_line_naming_file_line_and_key(body, error):
    with pytest.raises(ScenarioError) as err:
        parse('end = 9\n[[event]]\nat = 5\nkind = "expect"\n' + body)
    assert str(err.value).startswith(error) and "\n" not in str(err.value)


def test_an_expectation_after_the_end_is_an_error_even_when_its_since_is_not():
    with pytest.raises(ScenarioError, match=r"x.toml:3: at: 10 s is after the end \(9 s\)"):
        parse('end = 9\n[[event]]\nat = 10\nkind = "expect"\njoint = 1\nmoved_deg = 1\nsince = 5\n')


def test_an_expected_variable_must_be_watched_before_anything_runs(tmp_path):
    build = build_lab(LABS / "watch_inputs.c")
    cases = [('var = "mycount"\nvalue = 1\n', "s.toml:5: var: mycount is not a watched (#pragma "
              "DATA_SECTION) variable of watch_inputs.c (watched: gain, mode, table)"),
             ('var = "table"\nvalue = 1\n', "s.toml:5: index: table has 4 elements in watch_inputs.c: give "
              "an index 0..3"),
             ('var = "mode"\nindex = 1\nvalue = 1\n', "s.toml:5: index: mode is not an array in "
              "watch_inputs.c")]
    for body, expected in cases:
        s = parse_scenario('end = 9\n[[event]]\nat = 5\nkind = "expect"\n' + body, Path("s.toml"))
        with pytest.raises(ScenarioError) as err:
            check_lab(s, build)
        assert str(err.value) == expected
    fine = parse_scenario('end = 9\n[[event]]\nat = 5\nkind = "expect"\nvar = "table"\nindex = 3\n'
                          'value = 1e9\n', Path("s.toml"))
    check_lab(fine, build)  # an expected value need not fit the variable: it is only compared


def test_a_run_result_carries_its_expectations_through_grading_processes():
    import pickle

    s = parse('end = 9\n[[event]]\nat = 5\nkind = "expect"\nerror = 1\n')
    judge = Judge(s.events, "x.toml")
    judge.observed(observed(tick=5000))
    result = RunResult(RunStatus.UNMET, 9000, "1 of 1 expectations failed", expectations=judge.results())
    again = pickle.loads(pickle.dumps(result))
    assert again.failed_expectations == result.failed_expectations and again.diagnosis() == result.diagnosis()


@pytest.mark.parametrize("change", [{"tick": True}, {"error": 1.0}, {"motor_rad": [0.0, 0.0]},
                                    {"motor_rad": ["a", 0.0, 0.0]}, {"var": "1"}, {"motor_board": 3}])
def test_an_observation_from_the_worker_is_read_as_untrusted_data(change):
    from crslab.worker.worker_messages import observation

    raw = {"tick": 5000, "motor_board": "piccolo", "motor_board_off": 1, "motor_board_cutouts": 1, "error": 0,
           "motor_rad": [0.0, 0.1, 0.2], "var": 2.5}
    assert observation(raw) == observed(tick=5000, motor_board_off=True, motor_board_cutouts=1,
                                        motor_rad=(0.0, 0.1, 0.2), var=2.5)
    with pytest.raises(TypeError):
        observation({**raw, **change})
