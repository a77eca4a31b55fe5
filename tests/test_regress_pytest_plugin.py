"""The pytest plugin in a student's repository: three lines name the lab, the scenario and the
golden file; recording writes it, a later run checks it, and a wrong lab fails with the report."""

import shutil
import subprocess
import sys
from pathlib import Path

from crslab.regress.transcript import read_golden

LABS = Path(__file__).parent / "labs"

TEST_FILE = '''
def test_lab1_prints_the_tour(crslab_check):
    crslab_check("lab1.c", scenario="tour", golden="golden/lab1_tour.txt", duration_s=6.0)
'''


def pytest_in(folder, *args):
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *args], cwd=folder,
                          capture_output=True, text=True, timeout=120)


def test_record_then_check_then_a_wrong_lab_fails_with_the_report(tmp_path):
    repo = tmp_path / "repo"
    (repo / "tests").mkdir(parents=True)
    shutil.copy(LABS / "lab1_own_ik.c", repo / "tests" / "lab1.c")
    (repo / "tests" / "test_lab1.py").write_text(TEST_FILE)

    r = pytest_in(repo)  # no golden file yet: the failure says how to record it
    assert r.returncode == 1
    assert "no golden file yet; record it with 'pytest --crslab-record'" in r.stdout

    r = pytest_in(repo, "--crslab-record")
    assert r.returncode == 0, r.stdout
    golden = read_golden(repo / "tests" / "golden" / "lab1_tour.txt")
    assert golden.header["scenario"] == "tour" and golden.body.count(b"\n\r") == 12

    r = pytest_in(repo)
    assert r.returncode == 0, r.stdout

    lab = repo / "tests" / "lab1.c"
    lab.write_text(lab.read_text().replace("atan2(-s_in, r_in)", "atan2(s_in, r_in)"))
    r = pytest_in(repo)
    assert r.returncode == 1
    assert "lab1.c on tour against lab1_tour.txt: mismatch:" in r.stdout
    assert "line 3 at t = 4.100 s: number 2 is 76.25, expected -24.06" in r.stdout
    assert "Traceback" not in r.stdout


def test_a_lab_that_does_not_compile_fails_with_gccs_words(tmp_path):
    shutil.copy(LABS / "does_not_compile.c", tmp_path / "lab1.c")
    (tmp_path / "test_lab1.py").write_text(TEST_FILE)
    r = pytest_in(tmp_path, "--crslab-record")
    assert r.returncode == 1
    assert "lab1.c does not compile" in r.stdout and "Kp_gain" in r.stdout
