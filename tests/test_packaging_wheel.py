"""The slow packaging test (marked ``packaging``): what a student gets from ``pip install crslab``.

From a clean copy of this checkout (its tracked files, nothing built), ``python -m build`` makes
the sdist and then the wheel *from the sdist*, so the sdist is shown to hold what the wheel build
needs. The wheel goes into a fresh venv with its dependencies (from PyPI, or pip's cache), and
every command a student or TA uses runs from a folder outside the checkout, with a fresh build
cache so each lab is compiled from the files the wheel installed. Deselect with
``-m "not packaging"``.
"""

import os
import shutil
import subprocess
import sys
import tarfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

import pytest

from crslab.regress.transcript import read_golden

pytestmark = pytest.mark.packaging

ROOT = Path(__file__).resolve().parents[1]
LABS = Path(__file__).parent / "labs"
OWN_IK = LABS / "lab1_own_ik.c"
IK_SIGN = "atan2(-s_in, r_in)"  # th2 of lab1_own_ik.c's elbow-up IK


def run(*cmd, cwd=None, env=None, timeout=600):
    return subprocess.run([str(c) for c in cmd], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout)


def clean_copy(dest: Path) -> Path:
    """The checkout's tracked files as they are now (uncommitted edits included), without anything
    built or cached in it."""
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    for rel in filter(None, files.decode().split("\0")):
        src = ROOT / rel
        if src.is_file():
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / rel)
    return dest


@dataclass
class Installed:
    """A fresh venv holding the wheel, and a work folder outside the checkout."""

    venv: Path
    work: Path
    env: dict
    wheel: Path
    sdist: Path

    def crslab(self, *args, cwd=None, timeout=300):
        return run(self.venv / "bin" / "crslab", *args, cwd=cwd or self.work, env=self.env, timeout=timeout)


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> Installed:
    base = tmp_path_factory.mktemp("packaging")
    source = clean_copy(base / "crslab-src")
    dist = base / "dist"
    r = run(sys.executable, "-m", "build", "--outdir", dist, source)  # the sdist, then the wheel from it
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    [wheel], [sdist] = sorted(dist.glob("*.whl")), sorted(dist.glob("*.tar.gz"))
    venv = base / "venv"
    r = run(sys.executable, "-m", "venv", venv)
    assert r.returncode == 0, r.stderr
    r = run(venv / "bin" / "python", "-m", "pip", "install", "--quiet", "--no-compile", wheel, "pytest")
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    work = base / "work"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV", "CRSLAB_CACHE_DIR")}
    env.update(PATH=f"{venv / 'bin'}{os.pathsep}{os.environ['PATH']}", CRSLAB_CACHE_DIR=str(base / "cache"),
               PYTHONNOUSERSITE="1")
    return Installed(venv, work, env, wheel, sdist)


def test_the_sdist_and_the_wheel_carry_the_c_sources_and_the_models(installed):
    with tarfile.open(installed.sdist) as tar:
        in_sdist = {Path(*Path(n).parts[1:]).as_posix() for n in tar.getnames()}
    assert {"setup.py", "csrc/cffi_build.py", "csrc/sim/sim.h", "csrc/board/include/coecsl.h",
            "csrc/labs/lab1_kinematics.c", "models/crs_arm/scene.xml", "crslab/cheaders.py"} <= in_sdist
    with zipfile.ZipFile(installed.wheel) as whl:
        in_wheel = set(whl.namelist())
    assert {"crslab/_data/csrc/sim/sim.c", "crslab/_data/csrc/kin/crs_arm.h",
            "crslab/_data/csrc/board/include/coecsl.h", "crslab/_data/csrc/labs/lab2_tracking.c",
            "crslab/_data/models/crs_arm/scene.xml", "crslab/_data/models/crs_arm/params.toml",
            "crslab/scenarios/tour.toml", "crslab/robots/crs.toml"} <= in_wheel
    assert any(n.startswith("crslab/_core") and n.endswith(".so") for n in in_wheel)
    # crslab serve's page works offline: every script, style and licence is in the wheel
    assert {"crslab/serve/static/index.html", "crslab/serve/static/app.js",
            "crslab/serve/static/vendor/crslab-vendor.js",
            "crslab/serve/static/vendor/xterm.css", "crslab/serve/static/vendor/README.md",
            "crslab/serve/static/vendor/licenses/three-0.187.0.txt", "crslab/serve/templates/gen_a.c",
            "crslab/serve/deploy/nginx.conf"} <= in_wheel
    assert not any("/tests/" in n or n.endswith("cffi_build.py") for n in in_wheel)


def test_the_installed_package_finds_its_files_in_site_packages(installed):
    probe = ("import crslab, crslab.resources as r; print(crslab.__file__); print(r.path('csrc')); "
             "print(r.path('models'))")
    r = run(installed.venv / "bin" / "python", "-c", probe, cwd=installed.work, env=installed.env)
    assert r.returncode == 0, r.stderr
    for line in r.stdout.split():
        assert Path(line).is_relative_to(installed.venv) and "site-packages" in line, line


def test_sim_fast_and_fk(installed):
    r = installed.crslab("sim", "--fast", "--duration", "5", "--no-stdin")
    assert r.returncode == 0, r.stderr
    # Lab 1 is a Gen A lab: its printf truncates (x = 5.6357 in prints 5.63)
    assert r.stdout.splitlines() == ["0.00 -24.06 13.75", "5.63 0.00 16.75", "0.00 -24.06 13.75"] * 2
    assert r.stderr.startswith("crslab sim: lab1_kinematics.c on scenario tour for 5.0 s, as fast as it can.")
    r = installed.crslab("fk", "--motor-deg", "0", "90", "0")
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[0].split() == ["xyz", "(in)", "20.000", "0.000", "10.000"]


def test_record_with_offsets_check_and_the_pytest_fixture(installed):
    """A golden recorded with --offsets passes `crslab check` and the fixture in a student's repo."""
    repo = installed.work / "student-repo"
    (repo / "tests" / "golden").mkdir(parents=True)
    shutil.copy(OWN_IK, repo / "tests" / "lab1.c")
    golden = repo / "tests" / "golden" / "lab1_tour.txt"
    r = installed.crslab("record", "--lab", "tests/lab1.c", "--offsets", "-0.35", "0.3", "--duration", "7.5",
                         "-o", golden, cwd=repo)
    assert r.returncode == 0, r.stderr
    assert read_golden(golden).header["rest_motor_rad"] == "0.0 -0.35 0.3"
    r = installed.crslab("check", "--lab", "tests/lab1.c", "--golden", golden, cwd=repo)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.startswith("match: 21 lines")
    (repo / "tests" / "test_lab1.py").write_text(
        "def test_lab1(crslab_check):\n    crslab_check('lab1.c', golden='golden/lab1_tour.txt')\n")
    r = run(installed.venv / "bin" / "python", "-m", "pytest", "-q", "-p", "no:cacheprovider", cwd=repo,
            env=installed.env)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "1 passed" in r.stdout


def test_grade_a_folder_of_two(installed):
    subs = installed.work / "submissions"
    subs.mkdir()
    shutil.copy(OWN_IK, subs / "alice.c")
    text = OWN_IK.read_text()
    assert text.count(IK_SIGN) == 1
    (subs / "bob.c").write_text(text.replace(IK_SIGN, "atan2(s_in, r_in)"))
    shutil.copy(OWN_IK, installed.work / "reference.c")
    r = installed.crslab("grade", "submissions", "--reference", "reference.c", "--duration", "6",
                         "--jobs", "2", "--out", "grades")
    assert r.returncode == 1, r.stdout + r.stderr
    rows = (installed.work / "grades" / "grades.csv").read_text().splitlines()
    assert rows[1].startswith("alice.c,pass") and rows[2].startswith("bob.c,mismatch"), rows


def test_doctor(installed):
    r = installed.crslab("doctor")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "ok       lab build: lab1_kinematics.c compiles and links against the board" in r.stdout


def test_the_installed_serve_serves_its_page_and_its_vendored_scripts(installed):
    import http.client
    import re

    from waiting import LineWatcher, wait_exit

    proc = subprocess.Popen([installed.venv / "bin" / "crslab", "serve", "--port", "0"], cwd=installed.work,
                            env=installed.env, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True)
    try:
        line = LineWatcher(proc.stderr, "crslab serve's stderr").wait_for(r"http://")[-1]
        host = re.search(r"http://([^/]+)/", line).group(1)
        vendor = "vendor/crslab-vendor.js"
        for path, local in (("/", "index.html"), (f"/static/{vendor}", vendor)):
            conn = http.client.HTTPConnection(host, timeout=60)
            conn.request("GET", path)
            body = conn.getresponse().read()
            assert body == (ROOT / "crslab" / "serve" / "static" / local).read_bytes(), path
    finally:
        proc.terminate()
        wait_exit(proc, "SIGTERM")
