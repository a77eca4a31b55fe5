"""crslab/resources.py: the runtime files (csrc/, models/, scenarios, robots) are found through
importlib.resources; in this checkout they are the checkout's own, and from a package that is
not a plain folder (a zip) they are extracted once into the per-user cache, so a lab still
compiles and MuJoCo still loads the arm."""

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from crslab import resources
from crslab.lab import build

ROOT = Path(__file__).resolve().parents[1]


def test_the_editable_install_uses_the_checkouts_own_folders():
    assert resources.path("csrc") == ROOT / "csrc"
    assert resources.path("models", "crs_arm", "scene.xml") == ROOT / "models" / "crs_arm" / "scene.xml"
    assert resources.path("scenarios") == ROOT / "crslab" / "scenario" / "builtin"
    # every place that compiles or loads goes through it
    assert build.BOARD == ROOT / "csrc" / "board" and build.DEFAULT_LAB.is_file()
    with pytest.raises(ValueError, match="no runtime folder named 'tests'"):
        resources.folder("tests")


def zipped_package(tmp_path: Path, with_data: bool) -> Path:
    """crslab's Python files in a zip, laid out as the wheel lays them out (csrc/ and models/ in
    crslab/_data) when ``with_data``."""
    archive = tmp_path / "crslab.zip"
    with zipfile.ZipFile(archive, "w") as z:
        for p in sorted((ROOT / "crslab").rglob("*")):
            if p.is_file() and "__pycache__" not in p.parts and p.suffix != ".so":
                z.write(p, p.relative_to(ROOT).as_posix())
        if with_data:
            for top in ("csrc", "models"):
                for p in sorted((ROOT / top).rglob("*")):
                    if p.is_file() and "__pycache__" not in p.parts and "tests" not in p.parts:
                        z.write(p, f"crslab/_data/{p.relative_to(ROOT).as_posix()}")
    return archive


def compiled_core(tmp_path: Path) -> Path:
    """A folder holding only crslab's compiled core (``crslab/_core*.so``). Python loads no extension
    module from a zip, so a zipped crslab finds its core in a real folder added to the package's
    path; the editable install's import hook once did this implicitly from the checkout, and a
    plain .pth (pyproject's package-dir) does not."""
    core = tmp_path / "core"
    core.mkdir()
    sos = sorted((ROOT / "crslab").glob("_core*.so"))
    assert sos, "crslab._core is not built in this checkout"
    for so in sos:
        shutil.copy2(so, core / so.name)
    return core


PROBE = """
import sys
sys.path.insert(0, sys.argv[1])
import crslab
crslab.__path__.append(sys.argv[2])  # the compiled core only: every Python file comes from the zip
import mujoco
from crslab import resources
from crslab.lab.build import build_lab
from crslab.plant.model_files import SCENE_XML
assert resources.__file__.startswith(sys.argv[1]), resources.__file__
from crslab import _core
assert _core.__file__.startswith(sys.argv[2]), _core.__file__
b = build_lab()
m = mujoco.MjModel.from_xml_path(str(SCENE_XML))
print(resources.path("csrc"), b.image.is_file(), m.nq, SCENE_XML)
"""


def test_from_a_zip_the_files_are_extracted_into_the_cache_and_a_lab_builds(tmp_path):
    archive = zipped_package(tmp_path, with_data=True)
    core = compiled_core(tmp_path)
    cache = tmp_path / "cache"
    env = {"CRSLAB_CACHE_DIR": str(cache), "PATH": "/usr/bin:/bin"}
    r = subprocess.run([sys.executable, "-c", PROBE, str(archive), str(core)], capture_output=True, text=True,
                       env=env, timeout=120)
    assert r.returncode == 0, r.stderr
    csrc, built, nq, scene = r.stdout.split()
    assert Path(csrc).parent == cache / "resources" and Path(scene).is_relative_to(cache)
    assert (Path(csrc) / "board" / "tick.c").read_bytes() == (ROOT / "csrc" / "board" / "tick.c").read_bytes()
    assert built == "True" and nq == "3"
    # a second run reuses the extraction: still one copy of csrc
    r = subprocess.run([sys.executable, "-c", PROBE, str(archive), str(core)], capture_output=True, text=True,
                       env=env, timeout=120)
    assert r.returncode == 0, r.stderr
    assert len(list((cache / "resources").glob("csrc-*"))) == 1


def test_a_package_without_its_files_says_how_to_repair_it(tmp_path):
    archive = zipped_package(tmp_path, with_data=False)
    probe = ("import sys; sys.path.insert(0, sys.argv[1]); from crslab import resources; "
             "resources.path('csrc')")
    r = subprocess.run([sys.executable, "-c", probe, str(archive)], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 1
    assert r.stderr.strip().splitlines()[-1].endswith(
        "crslab's csrc folder is missing from its installation "
        f"({archive}/crslab/); reinstall it: pip install --force-reinstall crslab")


def test_crslab_from_an_installation_missing_its_files_is_one_line(tmp_path):
    """A command that needs the runtime files (``crslab sim`` builds a lab from csrc/) in an
    installation without them says how to repair it, in one line. (``crslab fk`` needs none of
    them: the CLI imports only the chosen command's module.)"""
    site = tmp_path / "site"
    shutil.copytree(ROOT / "crslab", site / "crslab", ignore=shutil.ignore_patterns("__pycache__"))
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--duration", "1"], cwd=tmp_path,
                       env={**os.environ, "PYTHONPATH": str(site)}, capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr == (f"crslab: crslab's csrc folder is missing from its installation ({site / 'crslab'}); "
                        "reinstall it: pip install --force-reinstall crslab\n")
