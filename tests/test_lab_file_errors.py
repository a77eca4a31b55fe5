"""A wrong path where a lab file or a serial folder belongs is one line naming what it is instead
(real subprocesses, as a user types them)."""

import subprocess
import sys
from pathlib import Path

import pytest

LAB = Path(__file__).parent / "labs" / "lab1_own_ik.c"


def crslab(*args, cwd):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=120, cwd=cwd)


@pytest.fixture
def course_folder(tmp_path):
    (tmp_path / "lab1.c").write_bytes(LAB.read_bytes())
    (tmp_path / "mylib.h").write_text("#define GAIN 2.0f\n")
    return tmp_path


@pytest.mark.parametrize("command", [["sim", "--fast"], ["record", "-o", "g.txt"], ["vars"], ["map"],
                                     ["sweep", "--vary", "friction=0.5:1", "--grid", "2", "-o", "s.csv"]])
def test_a_folder_given_as_the_lab_names_the_lab_files_in_it(course_folder, command):
    r = crslab(*command, "--lab", ".", cwd=course_folder)
    assert r.returncode == 2, r.stderr
    assert r.stderr.endswith(".: is a folder, not a lab file: give the lab file in it (lab1.c)\n"), r.stderr
    assert r.stderr.count("\n") == 1


@pytest.mark.parametrize("command", [["sim", "--fast"], ["vars"], ["debug", "--batch", "--ex", "bt"]])
def test_a_header_given_as_the_lab_says_so(course_folder, command):
    r = crslab(*command, "--lab", "mylib.h", cwd=course_folder)
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert "mylib.h: is a header, not a lab file: give the .c file that defines lab()" in r.stderr


def test_a_missing_lab_file_is_still_no_such_lab_file(course_folder):
    r = crslab("sim", "--lab", "lab2.c", cwd=course_folder)
    assert r.returncode == 2 and r.stderr == "crslab sim: lab2.c: no such lab file\n"


@pytest.mark.parametrize("extra", [[], ["--lab", "lab1.c"]])
def test_serial_read_from_a_folder_that_is_not_there(course_folder, extra):
    r = crslab("serial", "read", "offset_Enc2_rad", "--dir", "nope", *extra, cwd=course_folder)
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert "--dir nope: no such folder (start 'crslab sim --serial-dir nope' first" in r.stderr


def test_serial_read_from_a_folder_without_a_map_says_no_map(course_folder):
    (course_folder / "ports").mkdir()
    r = crslab("serial", "read", "offset_Enc2_rad", "--dir", "ports", cwd=course_folder)
    assert r.returncode == 2 and "ports: no .map files (give --map FILE)" in r.stderr


def test_a_transcript_given_as_the_lab_and_a_lab_given_as_the_golden_file_say_what_they_are(course_folder):
    (course_folder / "golden").mkdir()
    (course_folder / "golden" / "lab1_tour.txt").write_text("# crslab transcript\n# scenario: tour\n# ----\n")
    (course_folder / "notes.txt").write_text("angles 0.1 0.2\n")
    r = crslab("sim", "--fast", "--lab", "golden/lab1_tour.txt", cwd=course_folder)
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert r.stderr.endswith("golden/lab1_tour.txt: is a transcript (crslab record wrote it), not a lab "
                             "file: a lab is a .c file; a golden transcript goes to crslab check "
                             "--golden\n")
    r = crslab("sim", "--fast", "--lab", "notes.txt", cwd=course_folder)
    assert r.returncode == 2 and "notes.txt: is a text file, not a lab file" in r.stderr, r.stderr
    r = crslab("check", "--lab", "lab1.c", "--golden", "lab1.c", cwd=course_folder)
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert r.stderr.endswith("lab1.c: is a C file (a lab), not a golden transcript: record the lab's "
                             "transcript with crslab record --lab lab1.c -o golden.txt, then check "
                             "against golden.txt\n")
