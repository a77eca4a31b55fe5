"""`crslab grade` over a class: a good lab, a wrong one, one that does not compile, one that
crashes and one that hangs are each reported correctly, and grading finishes."""

import csv
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from crslab.regress.transcript import read_golden

LABS = Path(__file__).parent / "labs"
REFERENCE = Path(__file__).resolve().parents[1] / "csrc" / "labs" / "lab1_kinematics.c"


def crslab(*args, timeout=180):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout)


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    subs = tmp_path_factory.mktemp("submissions")
    shutil.copy(LABS / "lab1_own_ik.c", subs / "good.c")
    text = (LABS / "lab1_own_ik.c").read_text()
    (subs / "wrong.c").write_text(text.replace("atan2(-s_in, r_in)", "atan2(s_in, r_in)"))
    shutil.copy(LABS / "does_not_compile.c", subs / "broken.c")
    shutil.copy(LABS / "crash_after_5s.c", subs / "crash.c")
    shutil.copy(LABS / "hang_after_5s.c", subs / "hang.cpp")
    (subs / "notes.txt").write_text("not a lab")
    out = tmp_path_factory.mktemp("grades")
    r = crslab("grade", subs, "--reference", REFERENCE, "--scenario", "tour", "--duration", "8",
               "--deadline", "1", "--out", out)
    return r, out


def test_each_submission_is_classed_and_grading_finishes(graded):
    r, out = graded
    assert r.returncode == 1, r.stderr
    rows = {line.split()[0]: line for line in r.stdout.splitlines()[1:-1]}
    assert sorted(rows) == ["broken.c", "crash.c", "good.c", "hang.cpp", "wrong.c"]
    assert rows["good.c"].split()[1] == "pass"
    assert " mismatch " in rows["wrong.c"] and "line 3 (t = 4.100 s): number 2 is 76.24" in rows["wrong.c"]
    assert " does not compile " in rows["broken.c"] and "broken.c:9:13: error:" in rows["broken.c"]
    assert " crashed " in rows["crash.c"]
    assert "NULL pointer (its address was 0) at crash.c:27 in lab() at tick 5100" in rows["crash.c"]
    assert " hung " in rows["hang.cpp"]
    assert "lab() did not return within 1 s at tick 5100" in rows["hang.cpp"]
    assert r.stdout.splitlines()[-1] == (
        "5 submissions: 1 pass, 1 mismatch, 1 does not compile, 1 crashed, 1 hung")
    assert (out / "summary.txt").read_text() == r.stdout
    assert "[5/5]" in r.stderr and "Traceback" not in r.stderr


def test_csv_and_junit_reports(graded):
    _, out = graded
    with (out / "grades.csv").open() as f:
        rows = {row["submission"]: row for row in csv.DictReader(f)}
    assert {k: v["result"] for k, v in rows.items()} == {
        "broken.c": "does not compile", "crash.c": "crashed", "good.c": "pass", "hang.cpp": "hung",
        "wrong.c": "mismatch"}
    assert (rows["wrong.c"]["first_diff_line"], rows["wrong.c"]["first_diff_t_s"]) == ("3", "4.100")
    # 8 s: eight prints of three lines; the crash at 5.1 s comes before its third print's printing()
    assert rows["good.c"]["lines"] == "24" and rows["crash.c"]["lines"] == "2"  # partial transcript kept
    suite = ET.parse(out / "junit.xml").getroot()
    assert (suite.get("tests"), suite.get("failures"), suite.get("errors")) == ("5", "1", "3")
    cases = {c.get("name"): c for c in suite.iter("testcase")}
    assert cases["good.c"].find("failure") is None and cases["good.c"].find("error") is None
    assert "expected: 0.00 -24.06 13.75" in cases["wrong.c"].find("failure").text
    assert "Kp_gain" in cases["broken.c"].find("error").text
    assert (out / "reports" / "wrong.c.txt").is_file() and not (out / "reports" / "good.c.txt").exists()


def test_grade_transcripts_are_byte_identical_to_sim_and_record(graded, tmp_path):
    _, out = graded
    t, g = tmp_path / "t.txt", tmp_path / "g.txt"
    assert crslab("sim", "--fast", "--lab", LABS / "lab1_own_ik.c", "--duration", "8", "--transcript", t) \
        .returncode == 0
    assert crslab("record", "--lab", LABS / "lab1_own_ik.c", "--duration", "8", "-o", g).returncode == 0
    assert (out / "transcripts" / "good.c.txt").read_bytes() == t.read_bytes() == read_golden(g).body


def test_grade_bad_input(tmp_path):
    r = crslab("grade", tmp_path / "nowhere", "--reference", REFERENCE)
    assert r.returncode == 2 and r.stderr.strip().endswith("nowhere: no such folder of submissions")
    r = crslab("grade", tmp_path, "--reference", REFERENCE)
    assert r.returncode == 2 and r.stderr.strip().endswith(
        "no lab files (.c, .cpp) to grade, directly in it or in a folder per student")
    shutil.copy(LABS / "lab1_own_ik.c", tmp_path / "a.c")
    r = crslab("grade", tmp_path, "--reference", LABS / "does_not_compile.c", "--out", tmp_path / "o")
    assert r.returncode == 2 and r.stderr.strip().splitlines()[-1] == (
        "crslab grade: does_not_compile.c does not compile")
    r = crslab("grade", tmp_path, "--reference", LABS / "crash_after_5s.c", "--out", tmp_path / "o")
    assert r.returncode == 2 and r.stderr.strip().splitlines()[-1].startswith(
        "crslab grade: the reference lab did not run: crash_after_5s.c used a NULL pointer (its address "
        "was 0) at crash_after_5s.c:27 in lab() at tick 5100")


def test_a_submission_over_its_total_time_is_stopped_and_counts_as_hung(tmp_path):
    from crslab.regress.grade import run_many
    from crslab.run.api import make_config

    config = make_config(REFERENCE, "tour")
    [result] = run_many([LABS / "hang_after_5s.c"], config, 8000, jobs=1, deadline_s=60.0, timeout_s=1.5)
    assert result.status == "timeout" and result.status.graded(matched=False) == "hung"
    assert result.message == "hang_after_5s.c took longer than 1.5 s in all and was stopped"
    assert result.exit_status == 4 and result.lab_file == LABS / "hang_after_5s.c"
    # grades.csv's seconds: how long it really ran before it was stopped: past its 1.5 s (the
    # executor looks every 0.2 s), and short of the lab's own 60 s deadline, which did not stop it
    assert 1.5 < result.wall_s < 60.0


def test_the_progress_bar_on_a_terminal():
    import io

    from crslab.regress.grade import Progress

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    out = Terminal()
    bar = Progress(2, out)
    bar.update("good.c", "pass")
    bar.update("wrong.c", "mismatch")
    frames = out.getvalue().split("\r")[1:]
    assert frames[0].startswith("[" + "#" * 15 + "." * 15 + "] 1/2") and "good.c" in frames[0]
    assert frames[1].startswith("[" + "#" * 30 + "] 2/2") and frames[1].endswith("\n")


def test_a_class_exported_one_folder_per_student_is_graded_with_each_folders_files(tmp_path):
    """Gradescope and GitHub Classroom export a class as one folder per student: the folder's files
    are the submission, so a header of the student's own beside the lab compiles; a lab file
    directly in the class folder is graded alone, and its failure to find a header says so."""
    text = (LABS / "lab1_own_ik.c").read_text()
    own_header = text.replace('#include "math.h"', '#include "math.h"\n#include "my_offsets.h"').replace(
        "float offset_Enc2_rad = -0.42;", "float offset_Enc2_rad = MY_OFFSET2;")
    subs = tmp_path / "class"
    (subs / "alice").mkdir(parents=True)
    (subs / "alice" / "lab1.c").write_text(own_header)
    (subs / "alice" / "my_offsets.h").write_text("#define MY_OFFSET2 (-0.42f)\n")
    (subs / "bob" / "src").mkdir(parents=True)  # deeper, with a helper file that defines no lab()
    (subs / "bob" / "src" / "lab1.c").write_text(text.replace("atan2(-s_in, r_in)", "atan2(s_in, r_in)"))
    (subs / "bob" / "src" / "a_helper.c").write_text("int twice(int x) { return 2 * x; }\n")
    (subs / "carol").mkdir()
    (subs / "carol" / "README.md").write_text("I forgot my lab\n")
    (subs / ".git").mkdir()
    (subs / ".git" / "hook.c").write_text("void lab(void) { }\n")
    (subs / "dave.c").write_text(own_header)
    (subs / "my_offsets.h").write_text("#define MY_OFFSET2 (-0.42f)\n")
    out = tmp_path / "out"
    r = crslab("grade", subs, "--reference", LABS / "lab1_own_ik.c", "--duration", "4.2", "--out", out)
    assert r.returncode == 1, r.stderr
    assert "crslab grade: 3 submissions: 1 file, 2 folders; no lab file in carol/\n" in r.stderr
    rows = {line.split()[0]: line.split()[1] for line in r.stdout.splitlines()[1:-1]}
    assert rows == {"dave.c": "does", "alice/lab1.c": "pass", "bob/src/lab1.c": "mismatch"}
    dave = next(line for line in r.stdout.splitlines() if line.startswith("dave.c"))
    assert "dave.c:8:10: fatal error: 'my_offsets.h' file not found" in dave
    assert ("'my_offsets.h' file not found (my_offsets.h lies beside it, but a lab file directly in the "
            "class folder is graded alone: give each student with files of their own a folder, "
            "dave/dave.c and dave/my_offsets.h)") in (out / "reports" / "dave.c.txt").read_text()
    assert (out / "transcripts" / "alice" / "lab1.c.txt").read_bytes() == \
        (out / "transcripts" / "lab1_own_ik.c.reference.txt").read_bytes()
    assert (out / "reports" / "bob" / "src" / "lab1.c.txt").read_text().startswith("mismatch: ")
    with (out / "grades.csv").open() as f:
        assert sorted(row["submission"] for row in csv.DictReader(f)) == [
            "alice/lab1.c", "bob/src/lab1.c", "dave.c"]
