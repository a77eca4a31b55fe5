"""`crslab record` and `crslab check` as a student's CI runs them: golden round trip, a wrong lab's
report, JUnit, exit statuses, bad input in one line, and byte-identical transcripts at any speed."""

import hashlib
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from crslab import __version__
from crslab.regress.transcript import read_golden

NULL_AT = ("crash_after_5s.c used a NULL pointer (its address was 0) at crash_after_5s.c:27 in "
           "lab() at tick 5100")

LABS = Path(__file__).parent / "labs"
OWN_IK = LABS / "lab1_own_ik.c"
IK_SIGN = "atan2(-s_in, r_in)"  # th2 of the lab's elbow-up IK


def crslab(*args, timeout=120):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout)


def flipped_ik_lab(folder: Path) -> Path:
    """lab1_own_ik.c with one sign flipped in its IK."""
    text = OWN_IK.read_text()
    assert text.count(IK_SIGN) == 1
    path = folder / "lab1_flipped.c"
    path.write_text(text.replace(IK_SIGN, "atan2(s_in, r_in)"))
    return path


@pytest.fixture(scope="module")
def golden(tmp_path_factory):
    path = tmp_path_factory.mktemp("golden") / "lab1_tour.txt"
    r = crslab("record", "--lab", OWN_IK, "--scenario", "tour", "-o", path)
    assert r.returncode == 0, r.stderr
    written, cost = r.stderr.strip().splitlines()
    # what it wrote; then what --budget counted, as crslab sim's summary says it
    assert re.fullmatch(r"crslab record: lab\(\) x20900: mean [\d.,]+ instructions, max [\d,]+ instructions "
                        r"\(tick \d+\); 0 over the budget of 75,000 instructions", cost), cost
    assert written == f"crslab record: 126 lines (25.000 s simulated) written to {path}"
    return path


def test_record_writes_the_header_and_the_exact_transcript(golden, tmp_path):
    g = read_golden(golden)
    assert g.header["crslab"] == __version__
    assert g.header["lab"] == "lab1_own_ik.c"
    assert g.header["lab_sha256"] == hashlib.sha256(OWN_IK.read_bytes()).hexdigest()[:16]
    assert g.header["scenario"] == "tour" and g.header["end_s"] == "25.000"
    assert g.header["rest_motor_rad"] == "0.0 -0.42 0.24" and g.header["startup_delay"] == "yes"
    t = tmp_path / "t.txt"
    assert crslab("sim", "--fast", "--lab", OWN_IK, "--transcript", t).returncode == 0
    assert g.body == t.read_bytes() and g.body.count(b"\n\r") == 126


def test_golden_round_trip_matches(golden, tmp_path):
    junit = tmp_path / "j.xml"
    r = crslab("check", "--lab", OWN_IK, "--scenario", "tour", "--golden", golden, "--junit", junit)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.strip() == "match: 126 lines within abs tol 0.01, rel tol 0"
    suite = ET.parse(junit).getroot()
    assert (suite.get("tests"), suite.get("failures"), suite.get("errors")) == ("1", "0", "0")
    assert suite.find("testsuite/testcase").get("name") == "lab1_own_ik.c on tour"


def test_a_lab_with_one_sign_flipped_in_its_ik_fails_at_the_first_wrong_line_and_number(golden, tmp_path):
    junit = tmp_path / "j.xml"
    r = crslab("check", "--lab", flipped_ik_lab(tmp_path), "--golden", golden, "--junit", junit)
    assert r.returncode == 1
    report = r.stdout.splitlines()
    # the first print (t = 4.100 s): line 1 motor angles, line 2 x y z, line 3 the IK's motor angles
    assert report[0].startswith("mismatch: ") and "first at line 3 (t = 4.100 s): number 2 is 76.24, " \
        "expected -24.06 (off by 100.3)" in report[0]
    assert report[1].startswith("line 3 at t = 4.100 s: number 2 is 76.24, expected -24.06")
    assert report[2:4] == ["  expected: 0.00 -24.06 13.75", "  got:      0.00 76.24 114.06"]
    failure = ET.parse(junit).getroot().find("testsuite/testcase/failure")
    assert failure is not None and "line 3 at t = 4.100 s" in failure.text


def test_the_scenario_and_duration_default_to_the_golden_files(tmp_path):
    golden = tmp_path / "g.txt"
    assert crslab("record", "--scenario", "lab1_offsets", "--duration", "8.2", "-o", golden).returncode == 0
    assert crslab("check", "--golden", golden).returncode == 0
    r = crslab("check", "--golden", golden, "--scenario", "tour")
    assert r.returncode == 1 and "first at line 10 (t = 5.600 s)" in r.stdout.splitlines()[0]
    assert f"note: {golden} was recorded on scenario lab1_offsets, not tour" in r.stderr


def test_recording_a_lab_that_crashes_writes_nothing(tmp_path):
    out = tmp_path / "g.txt"
    r = crslab("record", "--lab", LABS / "crash_after_5s.c", "-o", out)
    assert r.returncode == 3 and not out.exists()
    assert r.stderr.strip() == f"crslab record: {NULL_AT} (t = 5.100 s); nothing was written"


def test_a_crash_while_checking_exits_as_the_simulator_does(golden):
    r = crslab("check", "--lab", LABS / "crash_after_5s.c", "--golden", golden)
    assert r.returncode == 3
    assert r.stdout.startswith(NULL_AT + " (t = 5.100 s)\n")
    assert "Traceback" not in r.stdout + r.stderr


@pytest.mark.parametrize("args, message", [
    (["check", "--golden", "no_such.txt"], "crslab check: no_such.txt: no such golden file"),
    (["check", "--golden", "{bad_header}"], "crslab check: {bad_header}: the crslab header has no end line"),
    (["check", "--golden", "{golden}", "--lab", "nowhere.c"], "crslab check: nowhere.c: no such lab file"),
    (["check", "--golden", "{golden}", "--scenario", "nowhere"], "crslab check: nowhere: no such scenario"),
    (["check", "--golden", "{golden}", "--abs-tol", "-1"], "crslab check: error: argument --abs-tol"),
    (["check", "--lab", "x.c"], "crslab check: error: the following arguments are required: --golden"),
    (["record", "--lab", LABS / "does_not_compile.c", "-o", "{tmp}/g.txt"],
     "crslab record: does_not_compile.c does not compile"),
    (["record", "-o", "{bad_header}/g.txt"], "crslab record: {bad_header}/g.txt: cannot write"),
])
def test_bad_input_is_one_line_and_status_2(golden, tmp_path, args, message):
    bad_header = tmp_path / "bad.txt"
    bad_header.write_text("# crslab transcript\n# scenario: tour\n")
    fill = {"golden": golden, "bad_header": bad_header, "tmp": tmp_path}
    r = crslab(*[str(a).format(**fill) for a in args])
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.strip().splitlines()[-1].startswith(message.format(**fill))
    assert "Traceback" not in r.stderr


def test_same_lab_and_scenario_are_byte_identical_at_fast_and_speed_3(tmp_path):
    fast, slow, rec = tmp_path / "fast.txt", tmp_path / "slow.txt", tmp_path / "rec.txt"
    args = ["--lab", OWN_IK, "--scenario", "tour", "--duration", "6"]
    assert crslab("sim", "--fast", *args, "--transcript", fast).returncode == 0
    assert crslab("sim", "--speed", "3", *args, "--transcript", slow).returncode == 0
    assert crslab("record", *args, "-o", rec).returncode == 0
    assert fast.read_bytes() == slow.read_bytes() == read_golden(rec).body
    assert fast.read_bytes().count(b"\n\r") == 12
