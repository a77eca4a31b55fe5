"""Hostile labs against the WebAssembly board (crslab's default): the native run sandbox's labs
(tests/labs/hostile/) and attacks aimed at the firmware itself (tests/labs/hostile_firmware/).
Each is named in one line and classed right, in ``crslab sim`` and in ``crslab grade``; only a
lab whose transcript matches passes; no secret appears anywhere; nothing is left behind.

The firmware is the lab linked with the framework's stand-ins, compiled to a WebAssembly module:
it computes on its own memory and can call only the board's functions. So a lab cannot reach the
pipe to crslab, a file, the clock or the environment (refused, named), cannot call what the board
does not have (it does not link), and its memory errors, runaway recursion, NULL pointers and
divisions by zero stop it at its line. Every hostile lab prints like the faulty labs and does its
deed on its 1024th call (tick 5123); a secret sits outside every lab folder (SECRET_PATH).

crslab compiles a lab with the C28x's widths (clang's AVR front end, crslab/lab/c28x_ir.py), where
C cannot name a WebAssembly import or builtin: the two attacks written with them do not build from a
lab file. The board's defences against such a module are tested with the module built for them by
zig's wasm32 front end (:func:`wasm32_firmware`).
"""

import csv
import os
import secrets
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NATIVE_HOSTILE = ROOT / "tests" / "labs" / "hostile"
FIRMWARE_HOSTILE = ROOT / "tests" / "labs" / "hostile_firmware"
HONEST = ROOT / "csrc" / "labs" / "lab1_kinematics.c"
BEFORE_FAULT = b"count 1 theta1 0.00\n\rcount 501 theta1 0.00\n\rcount 1001 theta1 0.00\n\r"
AT_5123 = "in lab() at tick 5123 (t = 5.123 s)"
BEFORE_FIRST_TICK = "in a constructor or static initializer before the first tick"
REFUSED = "was stopped by the sandbox: it tried to "

# lab -> (exit status of crslab sim, grade class, what its one line says: a start and an end)
EXPECTED = {
    # the native sandbox's labs, as firmware
    "read_file.c": (3, "forbidden", REFUSED + "open {secret} for reading at read_file.c:27", AT_5123),
    "write_file.c": (3, "forbidden", REFUSED + "open {target} for writing at write_file.c:27", AT_5123),
    "constructor_write.c": (3, "forbidden", REFUSED + "open {target} for writing at constructor_write.c:35",
                            BEFORE_FIRST_TICK),
    "read_environment.c": (3, "forbidden", REFUSED + "read the environment (getenv)", BEFORE_FIRST_TICK),
    "int80_open.c": (3, "forbidden", REFUSED + "open /etc/hostname for reading at int80_open.c:31", AT_5123),
    "pipe_pickle.c": (3, "forbidden", REFUSED + "use a file (fd_filestat_get) at pipe_pickle.c:41", AT_5123),
    "system_call.c": (2, "does not compile", "does not compile: it calls system(), which neither the file "
                      "nor the board's framework defines", ""),
    "ptrace_self.c": (2, "does not compile", "does not compile", ""),  # no <sys/ptrace.h> on the board
    "fork_child.c": (2, "does not compile", "does not compile", ""),
    "fork_bomb.c": (2, "does not compile", "does not compile", ""),
    "execve_shell.c": (2, "does not compile", "does not compile", ""),
    "kill_parent.c": (2, "does not compile", "does not compile", ""),
    "socket_connect.c": (2, "does not compile", "does not compile", ""),
    "parent_limits.c": (2, "does not compile", "does not compile", ""),
    "sigio_owner.c": (2, "does not compile", "does not compile", ""),
    "stat_file.c": (2, "does not compile", "does not compile", ""),
    "include_outside.c": (2, "does not compile", "does not compile", ""),
    # attacks on the firmware and the board
    "forge_verdict.c": (3, "forbidden", REFUSED + "write to descriptor 3 (a file or a pipe: the board has "
                        "none) at forge_verdict.c:28", AT_5123),
    "stat_secret.c": (3, "forbidden", REFUSED + "look up {secret} (stat) at stat_secret.c:27", AT_5123),
    "reads_the_clock.c": (3, "forbidden", REFUSED + "read the host's clock (time, clock, clock_gettime) at "
                          "reads_the_clock.c:24", AT_5123),
    "escape_sequences.c": (3, "forbidden", REFUSED + "open /tmp/\\x1b[2K\\x0d\\x1b[32mpass\\x1b[0m"
                           "\\u202e\\ufffe for reading at escape_sequences.c:25", AT_5123),
    "serial_send_out_of_range.c": (2, "does not compile", "does not compile: it calls board_send(), "
                                   "__builtin_wasm_memory_size()", ""),
    "wild_pointer.c": (3, "crashed", "read or wrote outside its memory (a wild pointer or an index far out "
                       "of an array) at wild_pointer.c:23", AT_5123),
    "console_flood.c": (6, "crashed", "printed more than 1 MB; the run was cut off at tick", ""),
    "huge_array.c": (2, "does not compile", "does not fit the board: its globals need 39,063 KB, the board "
                     "has 56 KB for its data (the largest, history, takes 39,062.5 KB)", ""),
    "undefined_call.c": (2, "does not compile", "does not compile: it calls set_gains(), which neither the "
                         "file nor the board's framework defines", ""),
    "device_include.c": (2, "does not compile", "does not compile", ""),
    # these run to their end: what they print is all a grade sees
    "big_allocation.c": (0, "mismatch", "", ""),
    "exists_oracle.c": (0, "mismatch", "", ""),
    "scribble_memory.c": (2, "does not compile", "does not compile: it calls __builtin_wasm_memory_size()",
                          ""),
}
WASM32_ONLY = ("serial_send_out_of_range.c", "scribble_memory.c")
"""Attacks that name WebAssembly's builtins or the board's import: run as :func:`wasm32_firmware`."""


class Place:
    """A secret and a target outside every lab folder, the labs (written for them), an empty working
    folder and a temporary folder of the test's own."""

    def __init__(self, base: Path) -> None:
        self.token = f"crslab-secret-{secrets.token_hex(12)}"
        self.secret = base / "secret" / "secret.txt"
        self.secret.parent.mkdir()
        self.secret.write_text(f"{self.token} = 1;\n")
        self.target = base / "outside" / "written.txt"
        self.target.parent.mkdir()
        self.labs = base / "labs"
        self.labs.mkdir()
        for lab in [*NATIVE_HOSTILE.glob("*.c"), *FIRMWARE_HOSTILE.glob("*.c")]:
            if lab.name in EXPECTED:
                text = lab.read_text().replace("SECRET_PATH", str(self.secret))
                (self.labs / lab.name).write_text(text.replace("TARGET_PATH", str(self.target)))
        self.cwd = base / "cwd"
        self.cwd.mkdir()
        self.tmp = base / "tmp"
        self.tmp.mkdir()
        self.env = {**os.environ, "CRSLAB_TEST_TOKEN": self.token, "TMPDIR": str(self.tmp)}

    def words(self, text: str) -> str:
        return text.format(secret=self.secret, target=self.target)

    def assert_untouched(self, *outputs: bytes) -> None:
        for out in outputs:
            assert self.token.encode() not in out
        assert list(self.target.parent.iterdir()) == []
        assert list(self.cwd.iterdir()) == []


@pytest.fixture(scope="module")
def place(tmp_path_factory):
    return Place(tmp_path_factory.mktemp("firmware-hostile"))


def test_every_lab_of_the_table_exists():
    labs = [*NATIVE_HOSTILE.glob("*.c"), *FIRMWARE_HOSTILE.glob("*.c")]
    assert sorted(EXPECTED) == sorted(p.name for p in labs if p.name in EXPECTED)
    # every attack aimed at the firmware is in the table
    assert {p.name for p in FIRMWARE_HOSTILE.glob("*.c")} <= set(EXPECTED)


@pytest.mark.parametrize("lab", sorted(EXPECTED))
def test_sim_names_and_classes_each_lab(place, lab):
    status, _, start, end = EXPECTED[lab]
    transcript = place.cwd.parent / f"{lab}.txt"
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--quiet", "--lab",
                        str(place.labs / lab), "--duration", "5.2", "--max-output-mb", "1", "--transcript",
                        str(transcript)],
                       capture_output=True, timeout=180, cwd=place.cwd, env=place.env)
    assert r.returncode == status, r.stderr.decode()[-1500:]
    assert b"Traceback" not in r.stderr
    assert b"\x1b" not in r.stderr  # no escape sequence reaches the terminal raw
    last = r.stderr.decode().strip().splitlines()[-1]
    if start:
        assert last.startswith(f"crslab sim: {lab} {place.words(start)}"), last
        assert last.endswith(end), last
    data = transcript.read_bytes() if transcript.exists() else b""
    if status in (3, 6) and lab != "constructor_write.c" and "constructor" not in end:
        assert data.startswith(BEFORE_FAULT)  # what it printed before is kept
    if lab == "console_flood.c":
        assert len(r.stdout) < 1000 and b"xxxx" not in r.stdout + r.stderr  # its 20 MB were never shown
        assert b"honest.c: pass" not in r.stderr
    if lab == "exists_oracle.c":  # the compiler sees nothing outside: the secret "does not exist" either
        assert data.startswith(b"count 1 theta1 0.00 exists 0 0\n\r")
    place.assert_untouched(r.stdout, r.stderr, data)


def wasm32_firmware(lab: Path, folder: Path):  # noqa: ANN201 - a LabBuild
    """The firmware of ``lab`` built by zig's wasm32 front end (the C library's own headers), linked
    with the framework's stand-ins as crslab links a lab: a module that may call the board's imports
    and use WebAssembly's builtins, which no lab file crslab compiles can."""
    import hashlib

    from crslab.cache import cache_dir, seal_file
    from crslab.generations import detect
    from crslab.lab import firmware, zig
    from crslab.lab.build import LabBuild, content_digest, text_memory
    from crslab.lab.entry_points import entry_calls

    text = lab.read_text()
    unit = folder / "unit.c"
    unit.write_text(f'#include "{lab}"\n{entry_calls(text)}')
    libc = firmware.prepare_zig()
    objects = firmware.firmware_objects(cache_dir(), content_digest)
    made, image = folder / "made.wasm", folder / "lab.wasm"
    r = subprocess.run([*zig.zig_cc(), f"--target={firmware.TARGET}", "-std=c11", "-O2", "-g",
                        *firmware.INCLUDES, *libc.compile_flags(), "-x", "c", str(unit), "-x", "none",
                        *map(str, objects), *map(str, libc.link), *firmware.LINK_FLAGS, "-o", str(made)],
                       capture_output=True, text=True, timeout=300, cwd=folder,
                       env=zig.zig_environment(folder / "zig-cache"))
    assert r.returncode == 0, r.stderr
    seal_file(made, image)  # as crslab's build keeps a module: the board opens only what this user sealed
    return LabBuild(source=lab, image=image, generation=detect(text), sanitized=False,
                    digest="wasm32-" + hashlib.sha256(image.read_bytes()).hexdigest()[:20],
                    memory=text_memory(text, lab.stem))


def test_a_module_built_for_wasm32_reaches_nothing_past_its_memory(place, tmp_path):
    """What the board does with a module that passes its import pointers past its memory, or that
    overwrites every byte of its memory: the two attacks, built for wasm32 (:func:`wasm32_firmware`)."""
    from crslab.run.api import simulate

    sent = simulate(build=wasm32_firmware(place.labs / "serial_send_out_of_range.c", tmp_path),
                    scenario="tour", duration_s=5.2)
    # the board read nothing outside the firmware's memory: 0 characters from past its end and from a
    # "negative" pointer, the 4 of 40 inside it; a length of -1 (4 GB) is refused whole
    assert sent.transcript == BEFORE_FAULT + b"END!|0 0 4\n\r"
    assert sent.status == "crashed" and sent.message.startswith(
        f"serial_send_out_of_range.c: a serial_printf {AT_5123} formatted 4294967295 characters; "), \
        sent.message
    scribbled = simulate(build=wasm32_firmware(place.labs / "scribble_memory.c", tmp_path), scenario="tour",
                         duration_s=5.2)
    assert scribbled.status == "ok", scribbled.message  # its own memory, nothing of the board's
    assert scribbled.transcript.startswith(BEFORE_FAULT)
    place.assert_untouched(sent.transcript, scribbled.transcript)


def test_a_lab_deep_in_folders_is_still_named_at_its_line(place, tmp_path):
    """The C library's frames sit above the lab's in wasmtime's backtrace, each with its path: a
    lab in a deep folder (and crslab in one) still gets its line."""
    deep = tmp_path.joinpath(*(["a-folder-with-a-long-name-" + "x" * 40] * 12))
    deep.mkdir(parents=True)
    shutil.copy(place.labs / "constructor_write.c", deep / "constructor_write.c")
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--quiet", "--lab",
                        str(deep / "constructor_write.c"), "--duration", "0.1"],
                       capture_output=True, timeout=180, cwd=place.cwd, env=place.env)
    assert r.returncode == 3, r.stderr.decode()[-1500:]
    assert f"for writing at constructor_write.c:35 {BEFORE_FIRST_TICK}" in r.stderr.decode()


def test_grade_passes_only_what_matches_and_every_report_is_safe(place, tmp_path):
    subs = tmp_path / "class"
    subs.mkdir()
    for lab in place.labs.glob("*.c"):
        shutil.copy(lab, subs / lab.name)
    shutil.copy(HONEST, subs / "honest.c")
    shutil.copy(HONEST, subs / '=HYPERLINK("x.example","pass").c')  # a name that is a formula
    out = tmp_path / "grades"
    r = subprocess.run([sys.executable, "-m", "crslab", "grade", str(subs), "--reference", str(HONEST),
                        "--scenario", "hands_off", "--duration", "5.2", "--max-output-mb", "1", "--jobs", "2",
                        "--out", str(out)],
                       capture_output=True, timeout=900, cwd=place.cwd, env=place.env)
    assert r.returncode == 1, r.stderr.decode()[-2000:]
    assert b"\x1b" not in r.stdout + r.stderr and b"Traceback" not in r.stderr
    with (out / "grades.csv").open(newline="") as f:
        rows = {row["submission"]: row for row in csv.DictReader(f)}
    assert rows["honest.c"]["result"] == "pass"
    formula = "'" + '=HYPERLINK("x.example","pass").c'
    assert rows[formula]["result"] == "pass"  # passes, and its cell starts with a quote, not a formula
    assert not any(cell.startswith(("=", "+", "-", "@")) for row in rows.values() for cell in row.values())
    for lab, (_, grade, start, _) in EXPECTED.items():
        assert rows[lab]["result"] == grade, rows[lab]
        if start and grade != "does not compile":
            assert rows[lab]["detail"].startswith(f"{lab} {place.words(start)}"), rows[lab]["detail"]
    passed = {name for name, row in rows.items() if row["result"] == "pass"}
    assert passed == {"honest.c", formula}
    # every report readable: no control character, valid XML
    for report in [out / "summary.txt", *(out / "reports").iterdir()]:
        text = report.read_text()
        assert not any(ord(ch) < 32 and ch not in "\n\t" for ch in text), report
        assert "\u202e" not in text and "\ufffe" not in text, report
    suite = ET.parse(out / "junit.xml").getroot()  # parses: valid XML whatever the labs printed
    assert int(suite.get("tests")) == len(EXPECTED) + 2
    # no secret anywhere; nothing written outside the run's folders; nothing left behind
    everything = [r.stdout, r.stderr] + [p.read_bytes() for p in out.rglob("*") if p.is_file()]
    place.assert_untouched(*everything)
    assert list(place.tmp.iterdir()) == []  # every job's temporary folder was removed


def test_the_shared_block_has_no_name_in_any_file_system(place):
    """What a run shares with its worker is a memfd: nothing in /dev/shm or the temporary folder to
    leave behind when a grader's time limit kills the run."""
    from crslab.run.api import make_config
    from crslab.run.board_run import BoardRun

    with BoardRun(make_config(HONEST, "hands_off")) as sim:
        maps = Path(f"/proc/{sim.worker_pid}/maps").read_text()
        ours = Path("/proc/self/maps").read_text()  # what a forked worker inherits is not the run's
        shared = [line for line in maps.splitlines() if "crslab-shared" in line]
        assert shared and all("memfd:crslab-shared" in line for line in shared)
        named = {line.split(None, 5)[5] for line in maps.splitlines() if "/dev/shm/" in line}
        inherited = {line.split(None, 5)[5] for line in ours.splitlines() if "/dev/shm/" in line}
        # the run mapped nothing of /dev/shm of its own (a semaphore an earlier test's multiprocessing
        # left, inherited by a forked worker, may have been unmapped here since: its name says whose)
        own = [n for n in named - inherited if not n.rsplit("/", 1)[-1].startswith(("pym-", "sem.mp-"))]
        assert not own, own
        assert not [n for n in os.listdir("/dev/shm") if "crslab" in n]
