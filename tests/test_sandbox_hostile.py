"""Hostile labs (tests/labs/hostile/) built natively (``--native``): each one is contained by the
run sandbox and named, in ``crslab sim`` and in ``crslab grade``; an honest lab still passes; no
secret's contents appear in any output or report; no file appears outside the run's folders. (The
same labs as WebAssembly firmware, crslab's default: tests/test_firmware_hostile.py.)

Every hostile lab prints like the faulty labs (``count 1``, ``count 501``, ``count 1001``) and
does its deed on its 1024th call, at tick 5123; the constructor and the includes act before the
first tick. A secret file holding a random token sits outside every lab folder, and so does the
path the labs try to write; the tests write both paths into the labs (SECRET_PATH, TARGET_PATH).
The same token is in crslab's environment, which a lab must not see either.
"""

import csv
import os
import platform
import secrets
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HOSTILE = ROOT / "tests" / "labs" / "hostile"
HONEST = ROOT / "csrc" / "labs" / "lab1_kinematics.c"
BEFORE_FAULT = b"count 1 theta1 0.00\n\rcount 501 theta1 0.00\n\rcount 1001 theta1 0.00\n\r"
AT_5123 = "in lab() at tick 5123 (t = 5.123 s)"
BEFORE_FIRST_TICK = "in a constructor or static initializer before the first tick"

# lab -> what the diagnosis says it tried (after "it tried to "), up to the variable part
IN_LAB = {
    "read_file.c": "open {secret} for reading",
    "write_file.c": "open {target} for writing",
    "system_call.c": "start a new process (clone",
    "fork_child.c": "start a new process (clone",
    "fork_bomb.c": "start a new process (clone",
    "execve_shell.c": "run the program /bin/sh",
    "socket_connect.c": "open a network socket (AF_INET)",
    "kill_parent.c": "send SIGKILL to process ",
    "ptrace_self.c": "call ptrace (PTRACE_TRACEME)",
    "big_allocation.c": "allocate 1024 MB at once",
    "stat_file.c": "look up {secret} (newfstatat)",
    "parent_limits.c": "read process ",
    "sigio_owner.c": "make descriptor 0 signal a process (fcntl command 8: F_SETOWN, O_ASYNC)",
    "int80_open.c": "make the open system call of another architecture (a 32-bit call)"
    if platform.machine() == "x86_64" else "open /etc/hostname for reading",
}


class Place:
    """A secret outside every lab folder, the labs (the include labs written for it), the path
    the writing labs aim at, and an empty working folder."""

    def __init__(self, base: Path) -> None:
        self.token = f"crslab-secret-{secrets.token_hex(12)}"
        self.secret_dir = base / "secret"
        self.secret_dir.mkdir()
        self.secret = self.secret_dir / "secret.txt"
        self.secret.write_text(f"{self.token} = 1;\n")
        self.target = base / "outside" / "written.txt"
        self.target.parent.mkdir()
        self.labs = base / "labs"
        self.labs.mkdir()
        for lab in HOSTILE.glob("*.c"):
            text = lab.read_text().replace("SECRET_PATH", str(self.secret))
            (self.labs / lab.name).write_text(text.replace("TARGET_PATH", str(self.target)))
        (self.labs / "notes.h").symlink_to(self.secret)
        self.cwd = base / "cwd"
        self.cwd.mkdir()
        self.tmp = base / "tmp"
        self.tmp.mkdir()
        self.env = {**os.environ, "CRSLAB_TEST_TOKEN": self.token, "TMPDIR": str(self.tmp)}

    def expected(self, lab: str) -> str:
        return IN_LAB[lab].format(secret=self.secret, target=self.target)

    def assert_untouched(self, *outputs: bytes) -> None:
        for out in outputs:
            assert self.token.encode() not in out
        assert not self.target.exists()
        assert list(self.target.parent.iterdir()) == []
        assert list(self.cwd.iterdir()) == []


@pytest.fixture(scope="module")
def place(tmp_path_factory):
    return Place(tmp_path_factory.mktemp("hostile"))


def sim(place, lab, *extra, duration="5.2", timeout=120):
    transcript = place.cwd.parent / "transcript.txt"
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--native", "--fast", "--lab",
                        str(place.labs / lab), "--duration", duration, "--transcript", str(transcript),
                        *extra],
                       capture_output=True, timeout=timeout, cwd=place.cwd, env=place.env)
    data = transcript.read_bytes() if transcript.exists() else b""
    transcript.unlink(missing_ok=True)
    return r, data


def last_line(r):
    return r.stderr.decode().strip().splitlines()[-1]


def no_process_left(path):
    return subprocess.run(["pgrep", "-f", str(path)], capture_output=True).stdout.strip() == b""


@pytest.mark.parametrize("lab", sorted(IN_LAB))
def test_sim_stops_a_hostile_lab_and_names_what_it_tried(place, lab):
    r, transcript = sim(place, lab)
    line = last_line(r)
    assert r.returncode == 3, r.stderr.decode()[-1500:]
    assert line.startswith(f"crslab sim: {lab} was stopped by the sandbox: it tried to {place.expected(lab)}")
    assert line.endswith(AT_5123)
    assert transcript == BEFORE_FAULT  # what it printed before is kept
    assert r.stdout == BEFORE_FAULT.replace(b"\n\r", b"\n")
    assert b"Traceback" not in r.stderr
    place.assert_untouched(r.stdout, r.stderr, transcript)
    assert no_process_left(place.labs / lab)


def test_sim_names_the_parent_a_lab_tried_to_kill(place):
    r, _ = sim(place, "kill_parent.c")
    assert "(crslab itself) " + AT_5123 in last_line(r)


def test_a_message_written_into_crslabs_pipe_is_never_unpickled(place):
    r, transcript = sim(place, "pipe_pickle.c")
    assert r.returncode == 3
    line = last_line(r)
    assert line.startswith("crslab sim: pipe_pickle.c was stopped by the sandbox: it tried to write "
                           "into crslab's pipe (the worker's reply names os.system) by tick ")
    # the lab wrote at tick 5123; the worker runs on until crslab reads the pipe, how far depends
    # on the machine's speed and load: a tick of the run from then on, never a time
    tick = int(line.split(" by tick ")[1].split()[0])
    assert 5123 <= tick < 25_000 and f"(t = {tick / 1000:.3f} s)" in line
    assert transcript == BEFORE_FAULT
    place.assert_untouched(r.stdout, r.stderr)  # the shell command in the pickle never ran


def test_a_lab_sees_no_environment_variable(place):
    r, transcript = sim(place, "read_environment.c", duration="5.3")
    assert r.returncode == 0, r.stderr.decode()[-1500:]
    assert transcript == BEFORE_FAULT
    place.assert_untouched(r.stdout, r.stderr, transcript)
    # the same lab without the sandbox prints crslab's whole environment, the token with it
    r, transcript = sim(place, "read_environment.c", "--no-sandbox", duration="5.3")
    assert f"CRSLAB_TEST_TOKEN={place.token}".encode() in transcript


def test_a_constructor_runs_inside_the_sandbox(place):
    r, transcript = sim(place, "constructor_write.c")
    assert r.returncode == 3
    assert last_line(r) == (f"crslab sim: constructor_write.c was stopped by the sandbox: it tried to open "
                            f"{place.target} for writing {BEFORE_FIRST_TICK}")
    assert transcript == b""
    place.assert_untouched(r.stdout, r.stderr)


@pytest.mark.parametrize("lab, name", [
    ("include_outside.c", "{secret}"),
    ("include_symlink.c", "notes.h"),
])
def test_an_include_outside_the_lab_folder_is_not_there(place, lab, name):
    """The compiler reads a private copy of the lab's folder (a link out of it is not copied) and
    says a file it was refused as it says a missing one: no message tells that the secret exists."""
    r, transcript = sim(place, lab)
    assert r.returncode == 2
    assert last_line(r) == f"crslab sim: {lab} does not compile"
    assert f"{name.format(secret=place.secret)}: No such file or directory" in r.stderr.decode()
    assert b"Permission denied" not in r.stderr
    assert transcript == b""
    place.assert_untouched(r.stdout, r.stderr)


def test_without_the_sandbox_the_same_labs_do_reach_the_secret(place):
    """The rule the tests above guard, broken on purpose: --no-sandbox lets the lab read."""
    r, transcript = sim(place, "read_file.c", "--no-sandbox", duration="6")
    assert r.returncode == 0
    assert "warning: --no-sandbox: the lab runs with your permissions" in r.stderr.decode()
    assert place.token.encode() in transcript
    r, _ = sim(place, "include_outside.c", "--no-sandbox")
    assert place.token.encode() in r.stderr  # gcc quotes the secret's first line


def test_a_sanitized_run_is_sandboxed_too(place):
    r, transcript = sim(place, "read_file.c", "--sanitize", timeout=240)
    assert r.returncode == 3
    assert last_line(r) == (f"crslab sim: read_file.c was stopped by the sandbox: it tried to open "
                            f"{place.secret} for reading {AT_5123}")
    assert transcript == BEFORE_FAULT
    place.assert_untouched(r.stdout, r.stderr, transcript)


def test_grade_classes_every_hostile_lab_forbidden_and_the_honest_one_pass(place, tmp_path):
    subs = tmp_path / "class"
    subs.mkdir()
    for lab in place.labs.glob("*.c"):
        shutil.copy(lab, subs / lab.name)
    (subs / "notes.h").symlink_to(place.secret)  # next to include_symlink.c, as in the lab folder
    (subs / "linked.c").symlink_to(place.secret)  # a submission that is a link out of the folder
    shutil.copy(HONEST, subs / "honest.c")
    before = {p.name: (p.is_symlink(), p.read_bytes() if not p.is_symlink() else b"") for p in subs.iterdir()}
    out = tmp_path / "grades"
    r = subprocess.run([sys.executable, "-m", "crslab", "grade", str(subs), "--reference", str(HONEST),
                        "--scenario", "hands_off", "--duration", "5.2", "--jobs", "2", "--out", str(out),
                        "--native"],
                       capture_output=True, timeout=600, cwd=place.cwd, env=place.env)
    assert r.returncode == 1, r.stderr.decode()[-2000:]
    rows = {row["submission"]: row for row in csv.DictReader((out / "grades.csv").open())}
    assert rows["honest.c"]["result"] == "pass"
    for lab in IN_LAB:
        assert rows[lab]["result"] == "forbidden", rows[lab]
        tried = place.expected(lab)
        assert rows[lab]["detail"].startswith(f"{lab} was stopped by the sandbox: it tried to {tried}")
        assert rows[lab]["detail"].endswith(AT_5123)
    assert rows["constructor_write.c"]["result"] == "forbidden"
    assert rows["constructor_write.c"]["detail"].endswith(BEFORE_FIRST_TICK)
    # a file outside is not there for the compiler, whether it exists or not (no existence oracle)
    assert rows["include_outside.c"]["result"] == "does not compile"
    assert f"{place.secret}: No such file or directory" in rows["include_outside.c"]["detail"]
    assert rows["pipe_pickle.c"]["result"] == "forbidden"
    assert "it tried to write into crslab's pipe" in rows["pipe_pickle.c"]["detail"]
    assert rows["linked.c"]["result"] == "forbidden"
    assert rows["linked.c"]["detail"] == (f"linked.c was stopped by the sandbox: it is a symbolic link to "
                                          f"{place.secret.resolve()}, outside the submissions folder")
    # built from a private copy of that one file: the class folder's notes.h is not there
    assert rows["include_symlink.c"]["result"] == "does not compile"
    assert "notes.h: No such file or directory" in rows["include_symlink.c"]["detail"]
    summary = (out / "summary.txt").read_text()
    forbidden = len(IN_LAB) + 3
    assert rows["read_environment.c"]["result"] == "mismatch"  # ran to its end, printing no variable
    assert summary.splitlines()[-1] == (f"{forbidden + 4} submissions: 1 pass, 1 mismatch, 2 does not "
                                        f"compile, 0 crashed, 0 hung, {forbidden} forbidden")
    junit = (out / "junit.xml").read_text()
    assert junit.count('<error message="forbidden: ') == forbidden
    # no secret anywhere, nothing written outside the run's folders, the class folder untouched
    everything = [r.stdout, r.stderr] + [p.read_bytes() for p in out.rglob("*") if p.is_file()]
    place.assert_untouched(*everything)
    after = {p.name: (p.is_symlink(), p.read_bytes() if not p.is_symlink() else b"") for p in subs.iterdir()}
    assert after == before
    assert list(place.tmp.iterdir()) == []
