"""Issue 31's attacks at the edges of the board, where a submission is compiled or its build is
looked up, each reproduced (each failed before the fix):

- finding 1: grade's C28x check compiled the class folder's file itself: an ``#embed`` of a
  neighbour's file under ``#if defined(__AVR__)`` showed its bytes in the report's warnings;
- finding 2: a cache folder another user owns (or planted where the fallback goes) was used, and a
  compiled firmware (``.cwasm``) planted in it ran in place of the user's lab;
- finding 3: builds were keyed by a pattern over ``#include`` lines: a header reached any other
  way was not in the key, so two folders differing only in it shared one build;
- finding 4: compilers outlived their job (crslab killed, SIGTERM, Ctrl-C, grade's --timeout);
- finding 9: a build killed on its time left the submission's text in the cache;
- finding 10: an include of an existing-but-forbidden file and of a missing one gave different
  answers (an existence oracle);
- and: no compiler ever runs on a submission outside the one contained way
  (crslab/lab/compile_process.py).

Processes are found by a marker in their environment (and their start time), never by pid alone:
pids wrap on a busy machine.
"""

import json
import os
import re
import secrets
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from waiting import wait_until

from crslab import cache as cache_module
from crslab.cli.regress_commands import c28x_reports
from crslab.lab import compile_process
from crslab.lab.build import build_lab
from crslab.lab.c28x_check import check_lab
from crslab.lab.compile_process import LabBuildError

ROOT = Path(__file__).resolve().parents[1]
FIRST_CALL = "4.2"
"""A run's length in s that reaches the framework's first call of lab() (at 4.1 s)."""
HONEST = ROOT / "csrc" / "labs" / "lab1_kinematics.c"
HEAD = '#include <tistdtypes.h>\n#include <coecsl.h>\n#include "user_includes.h"\n#include "math.h"\n'
BODY = """
float sign_used = TORQUE_SIGN;
long mycount = 0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = TORQUE_SIGN * 0.5f;
    *tau2 = 0;
    *tau3 = 0;
    if (mycount == 0) serial_printf(&SerialA, "sign %d\\n\\r", (int)TORQUE_SIGN);
    mycount++;
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
}
"""


@pytest.fixture(scope="module")
def shared_cache(tmp_path_factory):
    """One build cache for the module's tests that plant files in it or look into it (the firmware's
    own objects are built once into it)."""
    return tmp_path_factory.mktemp("cache")


@pytest.fixture(scope="module")
def build_cache():
    """The user's build cache, for the tests that only build in it: keyed by content, it holds the
    board's and the firmware's own objects already (built by any earlier test or run), so these tests
    compile only their labs."""
    return cache_module.cache_dir()


def with_sign(sign: int) -> str:
    return f"#define TORQUE_SIGN {sign}\n"


FLIPPED = "#define TORQUE_SIGN -1\n#else\n#define TORQUE_SIGN 1\n#endif\n"
# form -> (the lab's text before BODY, files of alice's folder, files of bob's folder): the two
# folders differ only in a header (its bytes, or whether it is there)
FORMS = {
    "digraph": ('%:include "signs.h"\n', {"signs.h": with_sign(1)}, {"signs.h": with_sign(-1)}),
    "comment": ('#include /*c*/ "signs.h"\n', {"signs.h": with_sign(1)}, {"signs.h": with_sign(-1)}),
    "line splice": ('#inc\\\nlude "signs.h"\n', {"signs.h": with_sign(1)}, {"signs.h": with_sign(-1)}),
    "import": ('#import "signs.h"\n', {"signs.h": with_sign(1)}, {"signs.h": with_sign(-1)}),
    "include_next": ('#include_next "signs.h"\n', {"signs.h": with_sign(1)}, {"signs.h": with_sign(-1)}),
    "macro": ('#define H "signs.h"\n#include H\n', {"signs.h": with_sign(1)}, {"signs.h": with_sign(-1)}),
    "header through a macro": (
        '#include "outer.h"\n',
        {"outer.h": '#define IN "signs.h"\n#include IN\n', "signs.h": with_sign(1)},
        {"outer.h": '#define IN "signs.h"\n#include IN\n', "signs.h": with_sign(-1)}),
    "__has_include": ('#if __has_include("flip.h")\n' + FLIPPED, {}, {"flip.h": "/* flip the signs */\n"}),
    "__has_embed": ('#if __has_embed("flip.bin")\n' + FLIPPED, {}, {"flip.bin": "x"}),
    "form feed": ('\f#include "signs.h"\n', {"signs.h": with_sign(1)}, {"signs.h": with_sign(-1)}),
}


def folder(base: Path, name: str, lab_text: str, files: dict[str, str]) -> Path:
    where = base / name
    where.mkdir()
    (where / "lab.c").write_text(lab_text)
    for file, text in files.items():
        (where / file).write_text(text)
    return where


@pytest.mark.parametrize("form", sorted(FORMS))
def test_two_folders_that_differ_only_in_a_header_get_two_builds(form, build_cache, tmp_path, monkeypatch):
    """alice and bob each build ``lab.c`` (byte-identical, given by the same name from their own
    folder) in one cache: bob's header is his, so his build is not alice's (finding 3)."""
    prefix, alice_files, bob_files = FORMS[form]
    text = HEAD + prefix + BODY
    alice = folder(tmp_path, "alice", text, alice_files)
    bob = folder(tmp_path, "bob", text, bob_files)
    monkeypatch.chdir(alice)
    a = build_lab(Path("lab.c"), cache=build_cache)
    monkeypatch.chdir(bob)
    b = build_lab(Path("lab.c"), cache=build_cache)
    assert a.digest != b.digest
    assert a.image.read_bytes() != b.image.read_bytes()
    # and each is found again (the key is cheap on a hit: no compile)
    monkeypatch.chdir(alice)
    assert build_lab(Path("lab.c"), cache=build_cache).image == a.image


def test_alice_and_bob_with_crslab_check(build_cache, tmp_path):
    """The issue's case end to end: bob's lab.c is byte-identical to alice's, his header (included
    through a macro) flips the torque signs; after alice ran in the same cache, bob's run prints
    what his own build prints (sign -1), not alice's."""
    prefix, alice_files, bob_files = FORMS["macro"]
    text = HEAD + prefix + BODY
    alice = folder(tmp_path, "alice", text, alice_files)
    bob = folder(tmp_path, "bob", text, bob_files)
    env = {**os.environ, "CRSLAB_CACHE_DIR": str(build_cache)}

    def run(where: Path) -> str:
        r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", "lab.c", "--fast", "--duration",
                            FIRST_CALL, "--no-c28x-check"], capture_output=True, text=True, cwd=where,
                           env=env, timeout=300)
        assert r.returncode == 0, r.stderr[-1500:]
        return r.stdout

    assert "sign 1" in run(alice)
    assert "sign -1" in run(bob)


def test_an_edited_header_is_built_anew(build_cache, tmp_path):
    """``record`` and ``sim`` after a header is edited run the edited code."""
    where = folder(tmp_path, "lab", HEAD + '#define H "signs.h"\n#include H\n' + BODY,
                   {"signs.h": with_sign(1)})
    first = build_lab(where / "lab.c", cache=build_cache)
    (where / "signs.h").write_text(with_sign(-1))
    second = build_lab(where / "lab.c", cache=build_cache)
    assert first.digest != second.digest
    (where / "signs.h").write_text(with_sign(1))
    assert build_lab(where / "lab.c", cache=build_cache).digest == first.digest


# -- finding 1: the C28x check reads only a private copy ------------------------------------------

SECRET = "Q7#"
LEAK = HEAD.replace('#include "math.h"\n', "") + "#if defined(__AVR__)\n" + "".join(
    f"signed char leak{i} = 1000 + (\n#embed \"neighbour.c\" clang::offset({i}) limit(1)\n);\n"
    for i in range(len(SECRET))) + "#endif\n"


def test_the_c28x_check_of_a_class_folder_never_shows_a_neighbours_bytes(tmp_path):
    """A submission that, only for the AVR analysis, embeds its neighbour's file one byte per
    constant: the report's "changes value from N" would list the bytes (finding 1)."""
    subs = tmp_path / "class"
    subs.mkdir()
    (subs / "neighbour.c").write_text(SECRET + "\n")
    (subs / "reference.c").write_text(HONEST.read_text())
    evil = subs / "evil.c"
    evil.write_text(LEAK + HONEST.read_text())
    report = c28x_reports([evil], sandboxed=True, jobs=1)[evil]
    said = " ".join(report.lines())
    for ch in SECRET:
        assert f"from {1000 + ord(ch)}" not in said, said
    assert report.findings == ()  # the neighbour is not there: the lab does not compile for the check
    # the same bytes in the lab's own text are checked as before (the copy is the lab)
    own = subs / "own.c"
    own.write_text(LEAK.replace("#embed \"neighbour.c\" clang::offset(0) limit(1)", str(ord("Q")))
                   .split("signed char leak1")[0] + "#endif\n" + HONEST.read_text())
    assert f"from {1000 + ord('Q')}" in " ".join(check_lab(own).lines())


@pytest.mark.parametrize("board", [pytest.param([], id="wasm"), pytest.param(["--native"], id="native")])
def test_grade_does_not_reveal_a_neighbours_bytes(tmp_path, board, build_cache):
    subs = tmp_path / "class"
    subs.mkdir()
    (subs / "neighbour.c").write_text(SECRET + "\n" + HONEST.read_text())
    (subs / "evil.c").write_text(LEAK + HONEST.read_text())
    out = tmp_path / "grades"
    r = subprocess.run([sys.executable, "-m", "crslab", "grade", str(subs), "--reference", str(HONEST),
                        "--scenario", "hands_off", "--duration", "1", "--jobs", "2", "--out", str(out),
                        *board],
                       capture_output=True, text=True, timeout=600,
                       env={**os.environ, "CRSLAB_CACHE_DIR": str(build_cache)})
    assert r.returncode in (0, 1), r.stderr[-2000:]
    everything = r.stdout + r.stderr + "".join(p.read_text("utf-8", "replace") for p in out.rglob("*")
                                               if p.is_file())
    for ch in SECRET:
        assert f"from {1000 + ord(ch)}" not in everything


# -- finding 10: no existence oracle ------------------------------------------------------------

def _answers(tmp_path: Path, build) -> list[str]:  # noqa: ANN001
    """What ``build`` says of a lab including a file that exists outside its folder and of one
    including a missing file (names of one length: a caret line underlines them), each name
    replaced by NAME."""
    secret = tmp_path / "outside" / "secret.h"
    secret.parent.mkdir()
    secret.write_text("int crs_secret = 1;\n")
    answers = []
    for name, target in (("there", secret), ("absent", tmp_path / "outside" / "absent.h")):
        lab_dir = tmp_path / name
        lab_dir.mkdir()
        (lab_dir / "lab.c").write_text(f'#include "{target}"\n' + HEAD + with_sign(1) + BODY)
        answers.append(build(lab_dir / "lab.c").replace(str(target), "NAME").replace(name, "LAB"))
    return answers


def _build_answer(lab: Path, **options) -> str:  # noqa: ANN003
    try:
        build_lab(lab, **options)
    except LabBuildError as exc:
        return f"{type(exc).__name__}: {exc}\n{exc.diagnostics}"
    return "built"


@pytest.mark.parametrize("native", [False, True], ids=["wasm", "native"])
def test_an_existing_forbidden_include_and_a_missing_one_get_the_same_answer(tmp_path, build_cache, native):
    there, missing = _answers(tmp_path, lambda lab: _build_answer(lab, cache=build_cache, native=native))
    assert there == missing
    assert "Permission denied" not in there and "crs_secret" not in there


def test_the_c28x_check_gives_the_same_answer_for_a_forbidden_and_a_missing_include(tmp_path):
    there, missing = _answers(tmp_path, lambda lab: check_lab(lab).skipped)
    assert there == missing and "file not found" in there


# -- the one contained compile ------------------------------------------------------------------

COMPILERS = ("zig", "cc", "gcc", "clang")


def test_every_compile_of_a_lab_goes_through_the_one_function(tmp_path, shared_cache, monkeypatch):
    """Every process started while a lab is built (WebAssembly, native) and checked (C28x) that
    runs a compiler is started by crslab.lab.compile_process, on the private copy: none names the
    lab's own folder."""
    lab_dir = tmp_path / f"labs-{secrets.token_hex(4)}"
    lab_dir.mkdir()
    lab = lab_dir / "lab.c"
    lab.write_text(f"/* {secrets.token_hex(8)} */\n" + HEAD + '#include "signs.h"\n' + BODY)
    (lab_dir / "signs.h").write_text(with_sign(1))
    started: list[tuple[list[str], str]] = []
    real_init = subprocess.Popen.__init__

    def spy(self, args, *rest, **kw):  # noqa: ANN001, ANN002, ANN003
        caller = sys._getframe(1)
        while caller is not None and caller.f_globals.get("__name__") == "subprocess":
            caller = caller.f_back
        argv = [str(a) for a in (args if isinstance(args, (list, tuple)) else [args])]
        if Path(argv[0]).name in COMPILERS or argv[0] in COMPILERS:
            started.append((argv, caller.f_globals.get("__name__", "") if caller else ""))
        return real_init(self, args, *rest, **kw)

    monkeypatch.setattr(subprocess.Popen, "__init__", spy)
    build_lab(lab, cache=shared_cache)
    build_lab(lab, cache=shared_cache, native=True)
    check_lab(lab)
    on_lab = [(argv, who) for argv, who in started if any(a.endswith(".c") and "firmware.c" not in a
                                                          and "generations.c" not in a for a in argv)]
    assert len(on_lab) >= 4  # wasm, native compile, the C28x check's two
    assert {who for _, who in on_lab} == {"crslab.lab.compile_process"}
    # anything else is a compiler asked about itself, on no file of anyone's
    probes = [argv for argv, who in started if who != "crslab.lab.compile_process"]
    assert all(set(argv) & {"--version", "-print-search-dirs", os.devnull} or
               any(a.startswith("-print-file-name=") for a in argv) for argv in probes), probes
    for argv, _ in on_lab:  # (a prefix map names the lab's folder for messages; nothing reads it)
        assert not any(str(lab_dir) in a for a in argv if "prefix-map=" not in a), argv


def test_nothing_in_crslab_starts_a_compiler_but_the_one_module():
    """A scan of crslab/: a process started with a compiler's command (zig_cc(), a Compiler's argv)
    anywhere but crslab/lab/compile_process.py is a compile nobody contains. The probes that ask a
    compiler about itself (``--version``, its search folders) never see a submission."""
    probes = {("crslab/lab/compiler.py", "-print-file-name"), ("crslab/lab/compiler.py", "--version"),
              ("crslab/sandbox/compile_sandbox.py", "-print-search-dirs"),
              ("crslab/sandbox/compile_sandbox.py", "os.devnull"),
              ("crslab/debug/tracer.py", "_GATE")}  # gdb (crslab debug), not a compiler
    starts = re.compile(r"subprocess\.(?:Popen|run|call|check_call|check_output)\("
                        r"|os\.(?:exec|spawn|posix_spawn)")
    found = []
    for path in sorted((ROOT / "crslab").rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if rel == "crslab/lab/compile_process.py":
            continue
        text = path.read_text()
        for m in starts.finditer(text):
            call = text[m.start():m.start() + 300]
            if re.search(r"zig_cc\(\)|zig_program\(\)|\bcc\.argv|\bself\.argv|\bcompiler\b|\*argv", call):
                if not any(rel == f and probe in call for f, probe in probes):
                    found.append(f"{rel}: {call.splitlines()[0]}")
    assert found == []


# -- finding 2: a cache only its owner writes ---------------------------------------------------

def test_a_cache_folder_another_user_owns_is_refused_with_one_line(tmp_path, monkeypatch):
    if os.geteuid() != 0:
        pytest.skip("giving a folder to another user needs root")
    theirs = tmp_path / "theirs"
    theirs.mkdir(mode=0o777)
    os.chown(theirs, 54321, 54321)
    monkeypatch.setenv("CRSLAB_CACHE_DIR", str(theirs))
    with pytest.raises(cache_module.CacheError) as caught:
        cache_module.cache_dir()
    assert str(caught.value) == (f"CRSLAB_CACHE_DIR={theirs} cannot be used as crslab's cache: it belongs to "
                                 "another user (uid 54321)")
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", str(HONEST), "--duration", "0.01",
                        "--fast"], capture_output=True, text=True, timeout=120,
                       env={**os.environ, "CRSLAB_CACHE_DIR": str(theirs)})
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert r.stderr.strip().splitlines()[-1].endswith("it belongs to another user (uid 54321)")
    assert list(theirs.iterdir()) == []


def test_the_fallback_in_tmp_is_never_someone_elses(tmp_path, monkeypatch):
    """A read-only home: the cache falls back to $TMPDIR/crslab-cache-UID. One planted there (a
    link) is refused with one line, and nothing is made in its place (issue 38: a fresh folder on
    every call left 15 per command, and every build then failed as "does not compile"; another
    user's folder there: tests/test_cache_owned.py)."""
    monkeypatch.delenv("CRSLAB_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", "/dev/null/no-home")  # cannot be made
    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr("tempfile.tempdir", None)
    planted = tmp_path / f"crslab-cache-{os.getuid()}"
    elsewhere = tmp_path / "attacker"
    elsewhere.mkdir(mode=0o777)
    planted.symlink_to(elsewhere)
    with pytest.raises(cache_module.CacheError, match=rf"{planted}: it is a symbolic link \(set "):
        cache_module.cache_dir()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["attacker", planted.name]
    assert list(elsewhere.iterdir()) == []
    planted.unlink()
    got = cache_module.cache_dir()
    assert got == planted == cache_module.cache_dir()  # one fallback, the same on every call
    st = got.lstat()
    assert st.st_uid == os.getuid() and st.st_mode & 0o777 == 0o700


def test_a_cache_folder_open_to_others_is_made_private(tmp_path, monkeypatch):
    mine = tmp_path / "mine"
    mine.mkdir()
    mine.chmod(0o777)
    monkeypatch.setenv("CRSLAB_CACHE_DIR", str(mine))
    assert cache_module.cache_dir() == mine
    assert mine.stat().st_mode & 0o777 == 0o700


def _sim_output(lab: Path, cache: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--fast", "--duration",
                           FIRST_CALL, "--no-c28x-check"], capture_output=True, text=True, timeout=300,
                          env={**os.environ, "CRSLAB_CACHE_DIR": str(cache)})


def test_a_planted_compiled_firmware_is_never_loaded(tmp_path, shared_cache):
    """wasmtime runs a ``.cwasm`` as machine code: another firmware's, planted under the name of
    this lab's, must not run in its place (finding 2), nor with the other's seal beside it."""
    cache = shared_cache
    mine = folder(tmp_path, "mine", HEAD + with_sign(1) + BODY, {}) / "lab.c"
    other = folder(tmp_path, "other", HEAD + with_sign(-1) + BODY, {}) / "lab.c"
    compiled = cache / "compiled"
    before = set(compiled.glob("*.cwasm")) if compiled.exists() else set()
    r = _sim_output(mine, cache)
    assert r.returncode == 0 and "sign 1" in r.stdout, r.stderr[-1500:]
    [mine_kept] = set(compiled.glob("*.cwasm")) - before
    r = _sim_output(other, cache)
    assert r.returncode == 0 and "sign -1" in r.stdout
    [other_kept] = set(compiled.glob("*.cwasm")) - before - {mine_kept}
    mine_kept.write_bytes(other_kept.read_bytes())  # planted under the name of mine's
    r = _sim_output(mine, cache)
    assert r.returncode == 0 and "sign 1" in r.stdout and "sign -1" not in r.stdout
    assert mine_kept.read_bytes() != other_kept.read_bytes()  # compiled anew
    seal = mine_kept.with_name(mine_kept.name + ".seal")
    mine_kept.write_bytes(other_kept.read_bytes())
    seal.write_text(other_kept.with_name(other_kept.name + ".seal").read_text())
    r = _sim_output(mine, cache)
    assert "sign 1" in r.stdout and "sign -1" not in r.stdout


def test_a_planted_build_is_never_loaded(tmp_path, shared_cache):
    """The same for a build: a lab.wasm planted in place of this lab's build is rebuilt."""
    lab = folder(tmp_path, "mine", HEAD + with_sign(1) + BODY, {}) / "lab.c"
    other = folder(tmp_path, "other", HEAD + with_sign(-1) + BODY, {}) / "lab.c"
    a = build_lab(lab, cache=shared_cache)
    b = build_lab(other, cache=shared_cache)
    a.image.write_bytes(b.image.read_bytes())
    again = build_lab(lab, cache=shared_cache)
    assert again.image.read_bytes() != b.image.read_bytes()


# -- finding 4 and 9: nothing outlives a job ----------------------------------------------------

SLOW = HEAD + with_sign(1) + '#include "slow.h"\n' + BODY
SLOW_HEADER = ('#if __INCLUDE_LEVEL__ < 120\n#include "slow.h"\n#include "slow.h"\n#endif\n')
"""A header that includes itself twice, 120 deep: 2^120 inclusions, little memory: the compiler
runs until it is stopped."""


def marked(marker: str) -> set[tuple[int, int]]:
    """(pid, start time) of every process whose environment holds ``marker``."""
    out = set()
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            env = Path(f"/proc/{entry}/environ").read_bytes()
            stat = Path(f"/proc/{entry}/stat").read_text()
        except OSError:
            continue
        if marker.encode() in env:
            out.add((int(entry), int(stat.rsplit(")", 1)[1].split()[19])))  # field 22: start time
    return out


def compilers(marker: str) -> set[tuple[int, int]]:
    found = set()
    for pid, start in marked(marker):
        try:
            exe = os.readlink(f"/proc/{pid}/exe")
        except OSError:
            continue
        if Path(exe).name in ("zig", "cc1", "clang", "gcc", "cc"):
            found.add((pid, start))
    return found


def still_running(procs: set[tuple[int, int]]) -> set[tuple[int, int]]:
    alive = set()
    for pid, start in procs:
        try:
            stat = Path(f"/proc/{pid}/stat").read_text()
        except OSError:
            continue
        fields = stat.rsplit(")", 1)[1].split()
        if int(fields[19]) == start and fields[0] != "Z":
            alive.add((pid, start))
    return alive


@pytest.mark.parametrize("how", ["SIGKILL", "SIGTERM", "SIGINT"])
@pytest.mark.parametrize("board", [pytest.param([], id="wasm"), pytest.param(["--native"], id="native")])
def test_no_compiler_outlives_crslab(tmp_path, shared_cache, how, board):
    lab = folder(tmp_path, "slow", SLOW, {"slow.h": SLOW_HEADER}) / "lab.c"
    marker = f"CRSLAB_TEST_MARK={secrets.token_hex(8)}"
    key, value = marker.split("=")
    proc = subprocess.Popen([sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--fast", "--duration",
                             "0.01", "--no-c28x-check", *board], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, env={**os.environ, key: value,
                                                         "CRSLAB_CACHE_DIR": str(shared_cache)})
    try:
        wait_until(lambda: bool(compilers(marker)), "the compiler's start")
        running = compilers(marker)
        proc.send_signal(getattr(signal, how))
        proc.wait(timeout=60)
        wait_until(lambda: not still_running(running), "the end of the compilers crslab started", 15)
        wait_until(lambda: not marked(marker), "the end of every process crslab started", 15)
    finally:
        proc.kill()
        proc.wait()


def test_grade_timeout_ends_the_compiler_and_leaves_no_text_in_the_cache(tmp_path, shared_cache):
    """A submission whose build runs past grade's --timeout: its job is killed; the compiler goes
    with it (finding 4), and nothing of its text stays in the cache or the temporary folder
    (finding 9)."""
    token = f"crslab_text_{secrets.token_hex(6)}"
    subs = tmp_path / "class"
    subs.mkdir()
    # a file of its own (grade builds it alone): it includes itself, twice at each of 120 levels
    (subs / "slow.c").write_text(f"/* {token} */\n#if __INCLUDE_LEVEL__ < 120\n#include __FILE__\n"
                                 "#include __FILE__\n#endif\n#ifndef CRS_ONCE\n#define CRS_ONCE\n"
                                 + HEAD + with_sign(1) + BODY + "#endif\n")
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    marker = f"CRSLAB_TEST_MARK={secrets.token_hex(8)}"
    key, value = marker.split("=")
    r = subprocess.run([sys.executable, "-m", "crslab", "grade", str(subs), "--reference", str(HONEST),
                        "--scenario", "hands_off", "--duration", "1", "--jobs", "2", "--timeout", "10",
                        "--no-c28x-check", "--out", str(tmp_path / "grades")],
                       capture_output=True, text=True, timeout=600,
                       env={**os.environ, key: value, "CRSLAB_CACHE_DIR": str(shared_cache),
                            "TMPDIR": str(tmp)})
    assert r.returncode in (1, 2), r.stderr[-2000:]
    wait_until(lambda: not marked(marker), "the end of every process grade started", 15)
    for where in (shared_cache, tmp):
        holding = [p for p in where.rglob("*") if p.is_file() and token.encode() in p.read_bytes()]
        assert holding == []
    rows = (tmp_path / "grades" / "grades.csv").read_text()
    assert "slow.c" in rows


def test_the_reaper_removes_a_build_whose_crslab_died(tmp_path):
    """The private build's folder (the submission's text) goes with crslab however it ends."""
    lab = tmp_path / "lab.c"
    lab.write_text("int secret_text;\n")
    code = ("import signal\nfrom pathlib import Path\nfrom crslab.lab.compile_process import PrivateBuild\n"
            f"b = PrivateBuild(Path({str(lab)!r}), b'int secret_text;', parent=Path({str(tmp_path)!r}))\n"
            "print(b.folder, flush=True)\nsignal.pause()\n")
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    made = Path(proc.stdout.readline().strip())
    assert (made / "submission" / "lab.c").read_text() == "int secret_text;"
    proc.kill()
    proc.wait()
    wait_until(lambda: not made.exists(), "the removal of the dead build's folder", 15)


def test_the_reaper_kills_the_compilers_group_when_crslab_dies(tmp_path):
    """A compiler's own children (zig cc's ``zig clang``, gcc's ``cc1``) do not get the parent-death
    signal: when crslab dies, the reaper kills them by the compiler's process group (/bin/sh may be
    dash, whose kill needs ``-s KILL -- -PGID``, not ``-KILL -- -PGID``)."""
    pid_file = tmp_path / "grandchild"
    code = ("import os, signal\nfrom crslab.lab.compile_process import start_compile\n"
            f"start_compile(['sh', '-c', 'sleep 300 & echo $! > {pid_file}; wait'], "
            "env={'PATH': os.environ['PATH']})\nprint('started', flush=True)\nsignal.pause()\n")
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "started"
        wait_until(lambda: pid_file.is_file() and pid_file.read_text().endswith("\n"), "the grandchild's id")
        pid = int(pid_file.read_text())
        start = int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[19])
        assert still_running({(pid, start)})
        proc.kill()
        proc.wait()
        wait_until(lambda: not still_running({(pid, start)}), "the end of the compiler's own child", 15)
    finally:
        proc.kill()
        proc.wait()


def test_a_compile_is_bounded_in_memory():
    assert compile_process.COMPILE_MEMORY_BYTES <= 2 * 1024 ** 3
    text = (ROOT / "docs" / "sandbox.md").read_text()
    assert f"{compile_process.COMPILE_MEMORY_BYTES // 2**30} GB of memory" in text


def test_json_of_a_kept_build_names_only_the_labs_folder(build_cache, tmp_path):
    """What a build records of the folder is names from the folder, never a path of the machine."""
    where = folder(tmp_path, "lab", HEAD + '#include "signs.h"\n' + BODY, {"signs.h": with_sign(1)})
    b = build_lab(where / "lab.c", cache=build_cache)
    record = json.loads((b.image.parent / "reads.json").read_text())
    assert sorted(record["reads"]) == ["signs.h"]
    assert record["listing"] == ["lab.c", "signs.h"]
