"""The sandbox's parts, each on its own: Landlock rulesets, the compile sandbox with gcc and
clang, the worker's one-thread rule, what a machine without Landlock does, and that the
sandbox never changes a transcript."""

import socket
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from crslab.lab.build import SHIM_INCLUDE
from crslab.run.api import simulate
from crslab.sandbox import landlock, seccomp, support
from crslab.sandbox.compile_sandbox import compiler_sandbox, forbidden_read
from crslab.sandbox.syscalls import PATH_ARGUMENT, path_argument_table

ROOT = Path(__file__).resolve().parents[1]
HONEST = ROOT / "csrc" / "labs" / "lab1_kinematics.c"


def run_python(code, *args, **kwargs):
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code), *map(str, args)],
                          capture_output=True, text=True, timeout=120, **kwargs)


def test_this_machine_has_every_protection():
    """CI's kernel has Landlock and seccomp: the sandbox is never silently off there."""
    assert support().missing == [], support().summary()
    assert support().summary().startswith("sandbox available: Landlock ABI ")


def test_landlock_lets_a_process_read_only_what_it_was_given(tmp_path):
    inside, outside = tmp_path / "inside", tmp_path / "outside"
    inside.mkdir()
    outside.mkdir()
    (inside / "a.txt").write_text("a")
    (outside / "b.txt").write_text("b")
    with socket.socket() as server:  # a TCP port on this machine that accepts connections
        server.bind(("127.0.0.1", 0))
        server.listen()
        r = run_python("""
            import socket, sys
            from crslab.sandbox.landlock import READ, Ruleset
            inside, outside, port = sys.argv[1], sys.argv[2], int(sys.argv[3])
            rules = Ruleset()
            rules.allow(inside, READ)
            rules.restrict_self()
            print(open(inside + "/a.txt").read())
            for what, act in (("read outside", lambda: open(outside + "/b.txt")),
                              ("write inside", lambda: open(inside + "/new.txt", "w")),
                              ("connect", lambda: socket.create_connection(("127.0.0.1", port)))):
                try:
                    act()
                    print(what, "allowed")
                except PermissionError:
                    print(what, "refused")
            """, inside, outside, server.getsockname()[1])
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[:3] == ["a", "read outside refused", "write inside refused"]
    assert lines[3] == ("connect refused" if landlock.abi_version() >= 4 else "connect allowed")
    assert not (inside / "new.txt").exists()


@pytest.mark.parametrize("compiler", ["gcc", pytest.param("clang", marks=pytest.mark.requires("clang"))])
def test_the_compile_sandbox_builds_a_lab_and_refuses_an_outside_include(compiler, tmp_path):
    lab, build, secret = tmp_path / "lab", tmp_path / "build", tmp_path / "secret.h"
    lab.mkdir()
    build.mkdir()
    secret.write_text("int secret_token_4242 = 1;\n")
    (lab / "ok.c").write_text('#include <math.h>\n#include <stdio.h>\n#include "coecsl.h"\n'
                              "double f(double x) { return sin(x); }\n")
    (lab / "bad.c").write_text(f'#include "{secret}"\n')
    box = compiler_sandbox([lab / "ok.c"], build, [SHIM_INCLUDE], compiler=compiler)

    def compile_in_box(name):
        rules = box.ruleset()
        try:
            return subprocess.run([compiler, "-std=c11", "-fPIC", "-shared", "-I", str(SHIM_INCLUDE),
                                   str(lab / name), "-o", str(build / "out.so"), "-lm"],
                                  capture_output=True, text=True, timeout=120, env=box.environment(),
                                  preexec_fn=box.preexec(rules.fd))
        finally:
            rules.close()

    ok = compile_in_box("ok.c")
    assert ok.returncode == 0, ok.stderr
    assert (build / "out.so").exists()
    bad = compile_in_box("bad.c")
    assert bad.returncode != 0
    assert forbidden_read(bad.stderr) == str(secret)
    assert "secret_token_4242" not in bad.stderr


def test_the_worker_must_be_one_thread_to_enter_the_sandbox():
    r = run_python("""
        import threading
        from crslab.sandbox.run_sandbox import SandboxError, enter_run_sandbox
        threading.Thread(target=threading.Event().wait, daemon=True).start()  # a second thread
        try:
            enter_run_sandbox(None, "/nonexistent.so", trap_library=None)
        except SandboxError as exc:
            print(exc)
        """)
    assert "the worker has 2 threads; the sandbox needs it to have one" in r.stdout, r.stderr


def test_path_arguments_are_known_for_the_file_calls():
    table = path_argument_table(1024)
    assert table[seccomp.number("openat")] == 1
    assert table[seccomp.number("execve")] == 0
    assert table[seccomp.number("write")] == 0xFF  # -1: no path
    assert all(seccomp.number(name) < 1024 for name in PATH_ARGUMENT)



def test_libseccomp_version_read_by_ctypes_is_cffis():
    """version() reads the library through ctypes (no C parser at a command's start); the filters'
    cffi declarations read the same struct."""
    ffi, lib = seccomp._library()
    v = lib.seccomp_version()
    assert seccomp.version() == (int(v.major), int(v.minor), int(v.micro))
    assert seccomp.version() >= (2, 0, 0)

# A machine whose kernel lacks Landlock, as inside a container whose seccomp profile refuses it:
# this wrapper makes landlock_create_ruleset fail with ENOSYS, then runs crslab.
WITHOUT_LANDLOCK = """
    import errno, os, sys
    from crslab.sandbox import seccomp
    f = seccomp.Filter(seccomp.ALLOW)
    f.add(seccomp.errno_action(errno.ENOSYS), "landlock_create_ruleset")
    f.load()
    os.execv(sys.executable, [sys.executable, "-m", "crslab", *sys.argv[1:]])
"""


def test_grade_refuses_to_run_without_landlock_unless_told(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    (subs / "honest.c").write_bytes(HONEST.read_bytes())
    grade = ["grade", subs, "--reference", HONEST, "--scenario", "hands_off", "--duration", "4.2",
             "--out", tmp_path / "out"]
    r = run_python(WITHOUT_LANDLOCK, *grade)
    assert r.returncode == 2
    line = r.stderr.strip().splitlines()[-1]
    assert line.startswith("crslab grade: the sandbox cannot run on this machine: it lacks Landlock "
                           "(Linux 5.13")
    assert line.endswith("give --no-sandbox to grade without it (every submission then runs with your "
                         "permissions)")
    assert not (tmp_path / "out").exists()
    r = run_python(WITHOUT_LANDLOCK, *grade, "--no-sandbox")
    assert r.returncode == 0, r.stderr
    assert "crslab grade: warning: --no-sandbox: the lab runs with your permissions" in r.stderr
    assert "1 submissions: 1 pass" in r.stdout


def test_sim_on_a_machine_without_landlock_warns_and_runs():
    r = run_python(WITHOUT_LANDLOCK, "sim", "--fast", "--duration", "4.2")
    assert r.returncode == 0, r.stderr
    assert "crslab sim: warning: running without the sandbox: this machine lacks Landlock" in r.stderr
    assert r.stdout.count("\n") == 3  # the run went on: Lab 1's three lines at 4.1 s


def test_doctor_names_a_missing_sandbox_and_still_passes():
    r = run_python(WITHOUT_LANDLOCK, "doctor")
    assert r.returncode == 0, r.stdout + r.stderr  # crslab sim runs (with a warning)
    line = next(x for x in r.stdout.splitlines() if x[9:].startswith("sandbox:"))
    assert line.startswith("missing  sandbox: this machine lacks Landlock (Linux 5.13")
    assert "crslab grade refuses to; fix: see docs/sandbox.md" in line
    assert "firmware ran 0.6 s on the board in a worker process" in r.stdout


def test_the_sandbox_never_changes_a_transcript():
    sandboxed = simulate(duration_s=12.0, sandbox=True).transcript
    assert sandboxed == simulate(duration_s=12.0, sandbox=False).transcript
    assert len(sandboxed) > 500
