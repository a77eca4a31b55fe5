"""The docs' commands run as written: docs/first-lab.md's blocks in order, in a student's fresh
folder, with the wheel installed by its own install block (tests/wheel_install.py); and
docs/autograder.md's grading command, Gradescope's setup.sh and run_autograder and PrairieLearn's
run.sh, with only their fixed roots (/autograder, /grade, /opt/crslab) moved into a temporary
folder and the apt-get lines left out (they need root and Debian's servers: CI's machine
installs the same packages). What the docs say a command prints is checked against what it
printed. Marked ``packaging``: it shares the packaging test's installed wheel."""

import fnmatch
import json
import re
import shutil
import signal
import subprocess
from pathlib import Path

import pytest
from waiting import LineWatcher, wait_exit
from wheel_install import DOCS, code_blocks

pytestmark = pytest.mark.packaging

LABS = Path(__file__).parent / "labs"
REFERENCE = LABS / "lab1_own_ik.c"
FIRST_LAB = DOCS / "first-lab.md"
AUTOGRADER = DOCS / "autograder.md"


def sh_blocks():
    return code_blocks(FIRST_LAB, "sh")


def test_first_lab_s_blocks_are_the_ones_this_test_runs():
    blocks = sh_blocks()
    assert [b.split()[:2] for b in blocks] == [["python3", "-m"], ["crslab", "sim"], ["crslab", "new"],
                                               ["crslab", "sim"], ["crslab", "record"]]


def test_first_lab_install_block_installed_the_wheel_and_doctor_passed(installed_wheel):
    assert (installed_wheel.work / installed_wheel.wheel.name).exists()
    doctor = installed_wheel.install_output
    assert "ok       lab build: lab1_kinematics.c compiles to a WebAssembly firmware" in doctor


def test_first_lab_first_run_prints_what_the_doc_shows(installed_wheel):
    """`crslab sim` runs at real time for 25 s: stopped with Ctrl-C, as the doc says, once the
    first scenario event has been announced (5 s in)."""
    block = sh_blocks()[1]
    assert block.strip() == "crslab sim"
    shown = re.search(r"runs crslab's own Lab 1.*?\n```\n(.*?)```", FIRST_LAB.read_text(), re.DOTALL)[1]
    shown_err = [line for line in shown.splitlines() if line.startswith("crslab sim: ")]
    shown_out = [line for line in shown.splitlines() if re.fullmatch(r"-?\d[-\d. ]*", line)]
    work = installed_wheel.work
    sim = subprocess.Popen(["bash", "-c", ". .venv/bin/activate\nexec " + block], cwd=work,
                           env=installed_wheel.env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
    try:
        err = LineWatcher(sim.stderr, "crslab sim's stderr")
        out = LineWatcher(sim.stdout, "crslab sim's stdout")
        err.wait_for(re.escape(shown_err[-1]))
        sim.send_signal(signal.SIGINT)  # Ctrl-C
        assert wait_exit(sim, "Ctrl-C") == 130
        stdout, stderr = out.all().splitlines(), err.all().splitlines()
    finally:
        sim.kill()
    assert stderr[0] == shown_err[0]  # crslab sim: lab1_kinematics.c on scenario tour for 25.0 s, ...
    assert shown_err[-1] in stderr  # the first event, in the doc's words
    assert stdout[:len(shown_out)] == shown_out
    assert any(line.startswith("crslab sim: interrupted at t = ") for line in stderr)


@pytest.fixture(scope="module")
def student_repo(installed_wheel):
    repo = installed_wheel.work / "lab1-repo"
    repo.mkdir()
    return repo


def test_first_lab_own_file_offsets_record_check_and_ci(installed_wheel, student_repo):
    blocks = sh_blocks()
    doc = FIRST_LAB.read_text()
    repo = student_repo
    r = installed_wheel.shell(blocks[2], cwd=repo)  # crslab new lab1 lab1.c; crslab sim --lab lab1.c --fast
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert len(lines) == 3 * 42 and lines[1:3] == ["0.00 0.00 0.00"] * 2  # "two lines of zeros"

    r = installed_wheel.shell(blocks[3], cwd=repo)  # the lab1_offsets scenario
    assert r.returncode == 0, r.stderr
    said = re.search(r"so at motor zero it reads `([-\d. ]+)`", doc)[1]
    assert said == "0.00 2.86 1.71"
    held = motor_lines_between(r.stdout, 8.0, 11.0)  # "holds it there from 8 s", until 11 s
    assert held and set(held) == {said}
    dh_zero = motor_lines_between(r.stdout, 13.5, 15.0)  # DH zero, "there from 13 s" (settled by 13.5 s)
    assert dh_zero and all(abs(float(line.split()[1]) - (90 + 2.86)) <= 0.015 for line in dh_zero), dh_zero
    # "with -0.42 and 0.24 it reads ..."
    right = re.search(r"with\s+-0\.42 and 0\.24 it reads `([-\d. ]+)`", doc)[1]
    text = (repo / "lab1.c").read_text()
    (repo / "lab1.c").write_text(text.replace("offset_Enc2_rad = -0.37", "offset_Enc2_rad = -0.42")
                                 .replace("offset_Enc3_rad = 0.27", "offset_Enc3_rad = 0.24"))
    r = installed_wheel.shell(blocks[3], cwd=repo)
    assert r.returncode == 0, r.stderr
    assert set(motor_lines_between(r.stdout, 8.0, 11.0)) == {right}
    assert all(abs(float(x)) <= 0.01 for x in right.split())  # zero, to the hand's 0.007 deg

    assert not (repo / "golden").exists()
    r = installed_wheel.shell(blocks[4], cwd=repo)  # crslab record --lab lab1.c -o golden/lab1_tour.txt
    assert r.returncode == 0, r.stderr
    assert (repo / "golden" / "lab1_tour.txt").is_file()
    check = re.search(r"`(crslab check --lab\s+lab1\.c --golden golden/lab1_tour\.txt)`", doc)[1]
    r = installed_wheel.shell(" ".join(check.split()), cwd=repo)
    assert r.returncode == 0 and r.stdout.startswith("match: "), r.stdout + r.stderr

    [test_file] = code_blocks(FIRST_LAB, "python")
    assert "Add `tests/test_lab1.py`" in doc
    (repo / "tests").mkdir()
    (repo / "tests" / "test_lab1.py").write_text(test_file)
    [workflow] = code_blocks(FIRST_LAB, "yaml")
    runs = re.findall(r"- run: (.*)", workflow)
    assert runs[0].startswith("pip install tools/crslab-*.whl pytest")  # the venv has them already
    for command in runs[1:]:  # crslab doctor, pytest
        r = installed_wheel.shell(command.split("#")[0], cwd=repo)
        assert r.returncode == 0, command + r.stdout + r.stderr
    assert "1 passed" in r.stdout


def motor_lines_between(stdout: str, from_s: float, to_s: float) -> list[str]:
    """Lab 1's first lines (the motor angles) printed from ``from_s`` to ``to_s``: it prints
    three lines every 0.5 s from 4.1 s."""
    lines = stdout.splitlines()
    out = []
    for i in range(0, len(lines) - 2, 3):
        t = 4.1 + 0.5 * (i // 3)
        if from_s <= t <= to_s:
            out.append(lines[i])
    return out


def test_first_lab_s_gen_b_snippet_matches_the_starting_file():
    [snippet] = code_blocks(FIRST_LAB, "c")
    from crslab.starters import starter_text

    assert "UARTprint = 1;" in snippet and "UARTprint = 1;" in starter_text("lab1", "B")
    assert "SWI_post(&SWI_printf);" in snippet and "SWI_post(&SWI_printf);" in starter_text("lab1", "A")


# --- docs/autograder.md ------------------------------------------------------------------------

def autograder_blocks():
    return {"sh": code_blocks(AUTOGRADER, "sh"), "bash": code_blocks(AUTOGRADER, "bash"),
            "toml": code_blocks(AUTOGRADER, "toml"), "dockerfile": code_blocks(AUTOGRADER, "dockerfile"),
            "zip": AUTOGRADER.read_text().split("Zip these files")[1]}


def moved(script: str, roots: dict[str, Path]) -> str:
    """``script`` with its fixed roots moved and its apt-get lines left out."""
    lines = [line for line in script.splitlines() if not line.startswith("apt-get")]
    text = "\n".join(lines) + "\n"
    for root, there in roots.items():
        text = text.replace(root, str(there))
    return text


@pytest.fixture(scope="module")
def autograder_zip(installed_wheel, tmp_path_factory):
    """The files of the zip the doc lists, in /autograder/source."""
    base = tmp_path_factory.mktemp("autograder")
    source = base / "autograder" / "source"
    source.mkdir(parents=True)
    blocks = autograder_blocks()
    listed = re.findall(r"^(\S+)", blocks["zip"].split("```")[1], re.MULTILINE)
    assert listed == ["setup.sh", "run_autograder", "lab1_reference.c", "tests.toml", "lab1_offsets.toml",
                      installed_wheel.wheel.name]  # the wheel the build makes, by its name
    shutil.copy(installed_wheel.wheel, source / installed_wheel.wheel.name)
    shutil.copy(REFERENCE, source / "lab1_reference.c")
    (source / "tests.toml").write_text(blocks["toml"][0])
    return base


def test_the_grading_command_as_written(installed_wheel, tmp_path):
    [command] = autograder_blocks()["sh"]
    folder = tmp_path / "SUBMISSION_DIR"
    folder.mkdir()
    shutil.copy(REFERENCE, folder / "lab1.c")
    shutil.copy(REFERENCE, tmp_path / "lab1_reference.c")
    (tmp_path / "tests.toml").write_text(autograder_blocks()["toml"][0])
    r = installed_wheel.shell(command, cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    results = json.loads((tmp_path / "results.json").read_text())
    assert results["score"] == 10 and [t["score"] for t in results["tests"]] == [6, 4]


def test_gradescope_setup_and_run_autograder_as_written(installed_wheel, autograder_zip):
    setup, run_autograder, _ = autograder_blocks()["bash"]
    roots = {"/autograder": autograder_zip / "autograder", "/opt/crslab": installed_wheel.venv}
    r = subprocess.run(["bash", "-c", moved(setup, roots)], cwd=autograder_zip, env=installed_wheel.env,
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert "ok       lab build" in r.stdout  # crslab doctor, in the image build log
    submission = autograder_zip / "autograder" / "submission"
    submission.mkdir()
    broken = REFERENCE.read_text().replace("atan2(-s_in, r_in)", "atan2(s_in, r_in)")
    (submission / "lab1.c").write_text(broken)
    (autograder_zip / "autograder" / "results").mkdir()
    r = subprocess.run(["bash", "-c", moved(run_autograder, roots)], cwd=autograder_zip,
                       env=installed_wheel.env, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    results = json.loads((autograder_zip / "autograder" / "results" / "results.json").read_text())
    assert results["score"] == 0 and {t["status"] for t in results["tests"]} == {"failed"}


def test_prairielearn_run_sh_as_written(installed_wheel, tmp_path):
    run_sh = autograder_blocks()["bash"][2]
    grade = tmp_path / "grade"
    for sub in ("tests", "student"):
        (grade / sub).mkdir(parents=True)
    shutil.copy(REFERENCE, grade / "tests" / "lab1_reference.c")
    (grade / "tests" / "tests.toml").write_text(autograder_blocks()["toml"][0])
    shutil.copy(REFERENCE, grade / "student" / "lab1.c")
    r = installed_wheel.shell(moved(run_sh, {"/grade": grade}), cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    results = json.loads((grade / "results" / "results.json").read_text())  # crslab makes results/
    assert results["score"] == 1.0 and results["gradable"] is True


def test_the_dockerfile_s_python_takes_the_wheel_it_copies(installed_wheel):
    from packaging.tags import cpython_tags
    from packaging.utils import parse_wheel_filename

    [dockerfile] = autograder_blocks()["dockerfile"]
    major, minor = map(int, re.search(r"^FROM python:(\d+)\.(\d+)", dockerfile, re.MULTILINE).groups())
    [copied] = re.findall(r"^COPY (\S+) /tmp/", dockerfile, re.MULTILINE)
    assert fnmatch.fnmatch(installed_wheel.wheel.name, copied)
    assert f"pip install --no-cache-dir /tmp/{copied}" in dockerfile
    tags = parse_wheel_filename(installed_wheel.wheel.name)[3]
    platform = next(iter(tags)).platform
    assert tags & set(cpython_tags((major, minor), platforms=[platform]))
    assert "|| true" not in dockerfile.split("pip install")[1].splitlines()[0]  # a failed install fails
