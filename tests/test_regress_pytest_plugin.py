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
    assert "line 3 at t = 4.100 s: number 2 is 76.24, expected -24.06" in r.stdout
    assert "Traceback" not in r.stdout


def test_a_lab_that_does_not_compile_fails_with_gccs_words(tmp_path):
    shutil.copy(LABS / "does_not_compile.c", tmp_path / "lab1.c")
    (tmp_path / "test_lab1.py").write_text(TEST_FILE)
    r = pytest_in(tmp_path, "--crslab-record")
    assert r.returncode == 1
    assert "lab1.c does not compile" in r.stdout and "Kp_gain" in r.stdout


GOLDEN_DEFAULTS_TESTS = '''
def test_golden_decides(crslab_check):
    crslab_check("lab1.c", golden="golden/offsets.txt")

def test_default_pose_instead(crslab_check):
    crslab_check("lab1.c", golden="golden/offsets.txt", rest_motor_rad=(0.0, -0.42, 0.24))

def test_startup_delay_instead(crslab_check):
    crslab_check("lab1.c", golden="golden/offsets.txt", startup_delay=True)
'''


def test_a_golden_recorded_with_offsets_passes_check_and_the_fixture_alike(tmp_path):
    """One reading of the header: the resting pose and the startup delay `crslab record` wrote are
    used by `crslab check` and by the fixture; overriding either one makes the same lab fail (the
    tour's hand takes the arm to an absolute pose at 5 s, which the lab reads through its offsets)."""
    repo = tmp_path / "repo"
    (repo / "tests" / "golden").mkdir(parents=True)
    lab = repo / "tests" / "lab1.c"
    shutil.copy(LABS / "lab1_own_ik.c", lab)
    golden = repo / "tests" / "golden" / "offsets.txt"
    crslab = [sys.executable, "-m", "crslab"]
    r = subprocess.run([*crslab, "record", "--lab", str(lab), "--offsets", "-0.35", "0.3",
                        "--no-startup-delay", "--duration", "7.5", "-o", str(golden)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    header = read_golden(golden).header
    assert header["rest_motor_rad"] == "0.0 -0.35 0.3" and header["startup_delay"] == "no"
    assert header["end_s"] == "7.500"

    r = subprocess.run([*crslab, "check", "--lab", str(lab), "--golden", str(golden)], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.strip() == "match: 45 lines within abs tol 0.01, rel tol 0"

    (repo / "tests" / "test_lab1.py").write_text(GOLDEN_DEFAULTS_TESTS)
    r = pytest_in(repo, "-rA")
    assert r.returncode == 1
    assert "PASSED tests/test_lab1.py::test_golden_decides" in r.stdout
    assert "FAILED tests/test_lab1.py::test_default_pose_instead" in r.stdout
    assert "FAILED tests/test_lab1.py::test_startup_delay_instead" in r.stdout
    assert "1 passed" in r.stdout and "2 failed" in r.stdout


def test_a_malformed_golden_header_fails_the_test_in_one_line(tmp_path):
    shutil.copy(LABS / "lab1_own_ik.c", tmp_path / "lab1.c")
    (tmp_path / "golden").mkdir()
    (tmp_path / "golden" / "lab1_tour.txt").write_text(
        "# crslab transcript\n# rest_motor_rad: 0 -0.42\n# ----\n0.00 -24.06 13.75\n\r")
    (tmp_path / "test_lab1.py").write_text(TEST_FILE)
    r = pytest_in(tmp_path)
    assert r.returncode == 1
    assert "lab1_tour.txt:2: rest_motor_rad: must be three angles within +-pi rad, got '0 -0.42'" in r.stdout
    assert "Traceback" not in r.stdout
