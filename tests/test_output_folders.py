"""Every command that writes a file or a folder makes the folders its path names, as
``crslab record --lab lab1.c -o golden/lab1_tour.txt`` in docs/first-lab.md expects of a fresh
repository (real subprocesses, in an empty folder)."""

import subprocess
import sys
from pathlib import Path

import pytest

from crslab.regress.transcript import read_golden

LABS = Path(__file__).parent / "labs"
LAB = LABS / "lab1_own_ik.c"
SQUARE = "x_in,y_in,z_in,t_s\n10,0,20,0\n12,-3,16,1.5\n10,0,20,3\n"


def crslab(*args, cwd):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=300, cwd=cwd)


def test_record_makes_the_golden_folder_as_first_lab_md_says(tmp_path):
    (tmp_path / "lab1.c").write_bytes(LAB.read_bytes())
    r = crslab("record", "--lab", "lab1.c", "--duration", "4.6", "-o", "golden/lab1_tour.txt", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    golden = read_golden(tmp_path / "golden" / "lab1_tour.txt")
    assert golden.header["lab"] == "lab1.c" and golden.body.count(b"\n") == 3  # one print at 4.1 s
    r = crslab("check", "--lab", "lab1.c", "--golden", "golden/lab1_tour.txt", "--junit", "reports/ci/j.xml",
               cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert (tmp_path / "reports" / "ci" / "j.xml").read_text().startswith("<?xml")


def test_a_run_s_files_go_into_new_folders(tmp_path):
    r = crslab("sim", "--lab", LAB, "--fast", "--quiet", "--no-stdin", "--duration", "4.2",
               "--transcript", "a/b/run.txt", "--csv", "c/run.csv", "--map", "d/lab.map", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "a" / "b" / "run.txt").read_bytes().replace(b"\r", b"") == r.stdout.encode()
    assert (tmp_path / "c" / "run.csv").read_text().count("\n") == 4201  # a header and a row a tick
    assert "offset_Enc2_rad" in (tmp_path / "d" / "lab.map").read_text()
    r = crslab("plot", "c/run.csv", "-o", "figs/run.png", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "figs" / "run.png").read_bytes().startswith(b"\x89PNG")


@pytest.mark.parametrize("args, made", [
    (["map", "--lab", LAB, "-o", "maps/x/lab1.map"], "maps/x/lab1.map"),
    (["traj", "crs", "--waypoints", "pts.csv", "-o", "out/traj.csv", "--plot", "figs/traj.png"],
     "out/traj.csv"),
    (["workspace", "planar3r", "--samples", "200", "-o", "figs/ws/ws.png"], "figs/ws/ws.png"),
])
def test_toolbox_outputs_make_their_folders(tmp_path, args, made):
    (tmp_path / "pts.csv").write_text(SQUARE)
    r = crslab(*args, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / made).stat().st_size > 0


def test_grade_makes_its_report_folder(tmp_path):
    (tmp_path / "subs").mkdir()
    (tmp_path / "subs" / "alice.c").write_bytes(LAB.read_bytes())
    r = crslab("grade", "subs", "--reference", LAB, "--duration", "4.2", "--jobs", "1", "-o", "reports/lab1",
               cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    rows = (tmp_path / "reports" / "lab1" / "grades.csv").read_text().splitlines()
    assert rows[1].startswith("alice.c,pass")


def test_a_folder_that_cannot_be_made_is_one_line(tmp_path):
    (tmp_path / "golden").write_text("a file, not a folder")
    r = crslab("record", "--lab", LAB, "--duration", "4.2", "-o", "golden/lab1.txt", cwd=tmp_path)
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert "golden/lab1.txt: cannot write the golden file" in r.stderr
