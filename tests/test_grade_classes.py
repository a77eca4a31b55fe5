"""Every grade class end to end, in ONE ``crslab grade`` run over tests/labs/grade_classes/: the
reference lab, a copy of it (pass) and one student mistake per file, each at call 1000
(t = 1.000 s, the startup delay off). The scenario (sets_gain.toml) writes the watched ``gain``
at 0.6 s; ``--strict`` makes a NaN torque end the run; ``--max-output-mb 0.002`` (2000 bytes)
cuts a flood off; ``--deadline 0.5`` calls a lab() that does not return hung.

Each submission's class is checked in grades.csv (with how its run ended and the exit status
``crslab check`` gives such a run), in the summary table, in its report and in junit.xml. The labs
run as WebAssembly firmware (crslab's default), whose diagnoses name the lab's line."""

import csv
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

LABS = Path(__file__).parent / "labs" / "grade_classes"
AT_1000 = "at tick 1000 (t = 1.000 s)"

# submission -> (grade class, run status, exit status of `crslab check`, the detail's words)
EXPECTED = {
    "pass.c": ("pass", "ok", 0, "6 lines match"),
    "mismatch.c": ("mismatch", "ok", 1,
                   "6 lines differ; line 1 (t = 0.000 s): number 2 is 1, expected 0 (off by 1)"),
    "segfault.c": ("crashed", "crashed", 3,
                   f"segfault.c used a NULL pointer (its address was 0) at segfault.c:31 in lab() "
                   f"{AT_1000}"),
    "calls_exit.c": ("crashed", "exited", 3,
                     f"calls_exit.c called exit(1) at calls_exit.c:32 in lab() {AT_1000}"),
    "hangs.c": ("hung", "hung", 4, f"hangs.c hung: lab() did not return within 0.5 s {AT_1000}"),
    "opens_file.c": ("forbidden", "forbidden", 3,
                     "opens_file.c was stopped by the sandbox: it tried to open /etc/hostname for reading at "
                     f"opens_file.c:31 in lab() {AT_1000}"),
    "typo.c": ("does not compile", "build-error", 2, "typo.c:26:21: error:"),
    "no_lab.c": ("does not compile", "no-lab", 2, "no_lab.c defines no lab() function"),
    "nan_torque.c": ("crashed", "nan", 5,
                     f"nan_torque.c returned a NaN or Inf in tau2 {AT_1000} and --strict is on"),
    "flood.c": ("crashed", "output-limit", 6,
                "flood.c printed more than 0.002 MB; the run was cut off at tick 1500 (t = 1.500 s)"),
    "unwatched.c": ("mismatch", "unfit", 2,
                    "sets_gain.toml:8: var: gain is not a watched (#pragma DATA_SECTION) variable of "
                    "unwatched.c"),
}


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    subs = tmp_path_factory.mktemp("class")
    for lab in LABS.glob("*.c"):
        if lab.name != "reference.c":
            shutil.copy(lab, subs / lab.name)
    shutil.copy(LABS / "reference.c", subs / "pass.c")
    out = tmp_path_factory.mktemp("grades")
    r = subprocess.run([sys.executable, "-m", "crslab", "grade", str(subs), "--reference",
                        str(LABS / "reference.c"), "--scenario", str(LABS / "sets_gain.toml"),
                        "--no-startup-delay", "--strict", "--deadline", "0.5", "--max-output-mb", "0.002",
                        "--jobs", "3", "--out", str(out)], capture_output=True, text=True, timeout=300)
    with (out / "grades.csv").open() as f:
        rows = {row["submission"]: row for row in csv.DictReader(f)}
    return r, out, rows


def test_the_folder_holds_one_lab_per_class(graded):
    _, _, rows = graded
    assert sorted(rows) == sorted(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_each_class_in_grades_csv(graded, name):
    _, _, rows = graded
    grade, status, exit_status, words = EXPECTED[name]
    row = rows[name]
    assert (row["result"], row["status"], int(row["exit_status"])) == (grade, status, exit_status), row
    assert words in row["detail"], row["detail"]


def test_the_transcripts_stop_where_each_run_stopped(graded):
    _, out, rows = graded
    reference = (out / "transcripts" / "reference.c.reference.txt").read_bytes()
    # six prints in 1.5 s (calls 0, 250, ..., 1250); the gain written at 0.6 s shows from call 750
    assert reference == b"".join(b"count %d gain %s\n\r" % (n, b"1.50" if n < 750 else b"2.50")
                                 for n in range(0, 1500, 250))
    assert (out / "transcripts" / "pass.c.txt").read_bytes() == reference
    # a run cut off at call 1000 keeps what it printed before (calls 0..750)
    for name in ("segfault.c", "calls_exit.c", "hangs.c", "opens_file.c"):
        assert rows[name]["lines"] == "4", name
        before = reference[:reference.index(b"count 1000")]
        assert (out / "transcripts" / f"{name}.txt").read_bytes() == before, name
    # the NaN of call 1000 ends the run after that tick's print
    assert rows["nan_torque.c"]["lines"] == "5"
    # the flood ends at its chunk's end: 2000 bytes kept of what fit the transmit ring
    assert len((out / "transcripts" / "flood.c.txt").read_bytes()) == 2000
    for name in ("typo.c", "no_lab.c", "unwatched.c"):
        assert (out / "transcripts" / f"{name}.txt").read_bytes() == b"", name


def test_the_summary_reports_and_exit_status(graded):
    r, out, _ = graded
    assert r.returncode == 1, r.stderr  # not every submission passed
    assert "Traceback" not in r.stderr and "3 at a time" in r.stderr  # --jobs 3
    table = {line.split()[0]: line for line in r.stdout.splitlines()[1:-1]}
    for name, (grade, *_) in EXPECTED.items():
        assert table[name].split(None, 1)[1].startswith(grade), table[name]
    assert r.stdout.splitlines()[-1] == (
        "11 submissions: 1 pass, 2 mismatch, 2 does not compile, 4 crashed, 1 hung, 1 forbidden")
    assert (out / "summary.txt").read_text() == r.stdout
    assert not (out / "reports" / "pass.c.txt").exists()
    for name, (grade, _, _, words) in EXPECTED.items():
        if name != "pass.c":
            report = (out / "reports" / f"{name}.txt").read_text()
            first = report.splitlines()[0]  # the grade said once: "hung: hangs.c hung: ..." is not
            assert first.startswith((f"{grade}: ", f"{name} {grade}: ")), report
            assert first.count(f"{grade}: ") == 1, report
            assert words in report and report.count(first) == 1, report
    assert "expected: count 0 gain 1.50" in (out / "reports" / "mismatch.c.txt").read_text()


def test_junit_failures_and_errors(graded):
    _, out, _ = graded
    suite = ET.parse(out / "junit.xml").getroot()
    assert (suite.get("tests"), suite.get("failures"), suite.get("errors")) == ("11", "2", "8")
    cases = {c.get("name"): c for c in suite.iter("testcase")}
    assert {n for n, c in cases.items() if c.find("failure") is not None} == {"mismatch.c", "unwatched.c"}
    assert cases["pass.c"].find("failure") is None and cases["pass.c"].find("error") is None
