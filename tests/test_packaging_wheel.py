"""The slow packaging test (marked ``packaging``): what a student gets from ``pip install crslab``.

The wheel is built from a clean copy of this checkout (the sdist first, the wheel from it) and
installed by docs/first-lab.md's install block into a fresh venv (tests/wheel_install.py); every
command a student or TA uses runs from a folder outside the checkout, with a fresh build cache.
Deselect with ``-m "not packaging"``.
"""

import os
import shutil
import subprocess
import tarfile
import zipfile
from pathlib import Path

import pytest
from wheel_install import NO_BYTECODE, run

from crslab.regress.transcript import read_golden

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.packaging

LABS = Path(__file__).parent / "labs"
OWN_IK = LABS / "lab1_own_ik.c"
IK_SIGN = "atan2(-s_in, r_in)"  # th2 of lab1_own_ik.c's elbow-up IK


@pytest.fixture
def installed(installed_wheel):
    return installed_wheel


def test_the_sdist_and_the_wheel_carry_the_c_sources_and_the_models(installed):
    with tarfile.open(installed.sdist) as tar:
        in_sdist = {Path(*Path(n).parts[1:]).as_posix() for n in tar.getnames()}
    assert {"setup.py", "csrc/cffi_build.py", "csrc/board/board.h", "csrc/firmware/include/coecsl.h",
            "csrc/labs/lab1_kinematics.c", "models/crs_arm/scene.xml", "crslab/cheaders.py"} <= in_sdist
    with zipfile.ZipFile(installed.wheel) as whl:
        in_wheel = set(whl.namelist())
    assert {"crslab/_data/csrc/board/tick.c", "crslab/_data/csrc/kin/crs_arm.h",
            "crslab/_data/csrc/firmware/include/coecsl.h", "crslab/_data/csrc/labs/lab2_tracking.c",
            "crslab/_data/models/crs_arm/scene.xml", "crslab/_data/models/crs_arm/params.toml",
            "crslab/scenario/builtin/tour.toml", "crslab/robots/crs.toml", "crslab/worlds/contest.toml",
            "crslab/_data/csrc/plant/world.c", "crslab/_data/csrc/plant/world.h"} <= in_wheel
    assert any(n.startswith("crslab/_core") and n.endswith(".so") for n in in_wheel)
    # crslab serve's page works offline: every script, style and licence is in the wheel
    assert {"crslab/serve/static/index.html", "crslab/serve/static/app.js",
            "crslab/serve/static/vendor/crslab-vendor.js",
            "crslab/serve/static/vendor/xterm.css", "crslab/serve/static/vendor/README.md",
            "crslab/serve/static/vendor/licenses/three-0.187.0.txt", "crslab/starters/lab1.c.tmpl",
            "crslab/serve/deploy/nginx.conf"} <= in_wheel
    assert not any("/tests/" in n or n.endswith("cffi_build.py") for n in in_wheel)


def test_the_wheel_is_abi3_and_installs_on_every_cpython_from_3_11(installed):
    """One wheel for every CPython >= 3.11 (Ubuntu 24.04's 3.12 included): tagged cp311-abi3, its
    C core the stable ABI's ``_core.abi3.so``; a second CPython on this machine installs it."""
    from packaging.tags import Tag, cpython_tags
    from packaging.utils import parse_wheel_filename

    name, version, _, tags = parse_wheel_filename(installed.wheel.name)
    assert {(t.interpreter, t.abi) for t in tags} == {("cp311", "abi3")}, installed.wheel.name
    platform = next(iter(tags)).platform
    for minor in (11, 12, 13, 14):  # what pip on each CPython accepts includes the wheel's tag
        accepted = set(cpython_tags((3, minor), platforms=[platform]))
        assert Tag("cp311", "abi3", platform) in accepted, minor
    assert Tag("cp311", "abi3", platform) not in set(cpython_tags((3, 10), platforms=[platform]))
    with zipfile.ZipFile(installed.wheel) as whl:
        cores = [n for n in whl.namelist() if n.startswith("crslab/_core")]
        wheel_meta = whl.read(f"{name}-{version}.dist-info/WHEEL").decode()
    assert cores == ["crslab/_core.abi3.so"]
    assert "Root-Is-Purelib: false" in wheel_meta
    no_bytecode = {**os.environ, **NO_BYTECODE}  # pip compiles nothing ahead (tests/wheel_install.py)
    for python in other_cpythons():  # where this machine has another CPython: the wheel installs there
        venv = installed.work / f"venv-{python.parent.parent.name}"
        assert run(python, "-m", "venv", venv, env=no_bytecode).returncode == 0
        r = run(venv / "bin" / "python", "-m", "pip", "install", "--quiet", "--no-deps", installed.wheel,
                "numpy", "cffi", env=no_bytecode)  # what the C core and the kinematics need; not MuJoCo
        assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
        r = run(venv / "bin" / "python", "-c", "from crslab import crs; print(crs.fk([0, 1.5707963268, 0]))",
                cwd=installed.work)
        assert r.returncode == 0 and r.stdout.split() == ["[20.", "0.", "10.]"], r.stdout + r.stderr


def other_cpythons() -> list[Path]:
    """The CPythons from 3.12 on that this machine has besides the one running the tests (on PATH as
    ``python3.N``, or installed by pyenv), one per version."""
    found: dict[str, Path] = {}
    candidates = [shutil.which(f"python3.{m}") for m in range(12, 16)]
    candidates += [str(p) for p in sorted(Path.home().glob(".pyenv/versions/3.*/bin/python3"))]
    for candidate in filter(None, candidates):
        r = run(candidate, "-c", "import sys; print('%d.%d' % sys.version_info[:2], sys.prefix)")
        if r.returncode != 0:
            continue  # a pyenv shim of a version that is not selected
        version, prefix = r.stdout.split()
        if tuple(map(int, version.split("."))) >= (3, 12) and version not in found:
            found[version] = Path(prefix) / "bin" / "python3"
    return list(found.values())


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
    assert ("ok       lab build: lab1_kinematics.c compiles to a WebAssembly firmware with the framework's "
            "stand-ins") in r.stdout


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
