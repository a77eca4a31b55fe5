"""The compiler is contained, whatever the lab file makes it do: a FIFO or a device named by an
``#include`` is refused before the compiler opens it, a compiler out of time is killed with every
process it started, its address space is bounded, and an image over 8 MB never reaches the build
cache. Both boards: the WebAssembly build (zig) and the native one (the host's compiler)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest
from waiting import wait_until

from crslab.lab.compile_process import IMAGE_CAP_BYTES, run_compile
from crslab.lab.includes import local_includes

LAB_BODY = ("void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,\n"
            "         float *tau3, int error)\n{\n    *tau1 = 0; *tau2 = 0; *tau3 = 0;\n}\n")
BOARDS = [pytest.param([], id="wasm"), pytest.param(["--native"], id="native")]


def sim(lab: Path, *extra: str, cache: Path | None = None) -> subprocess.CompletedProcess:
    """``crslab sim`` on ``lab``; ``cache``: a build cache of its own (zig's C library stays in the
    user's, which a fresh cache would build again)."""
    env = {**os.environ, "CRSLAB_CACHE_DIR": str(cache)} if cache is not None else None
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--fast", "--quiet",
                           "--duration", "0.01", "--no-c28x-check", *extra], capture_output=True, text=True,
                          env=env, timeout=300)


@pytest.mark.parametrize("board", BOARDS)
def test_an_include_of_a_fifo_in_the_labs_folder_does_not_compile_at_once(tmp_path, board):
    """Opening a FIFO blocks until someone writes to it: without the check the compiler would
    wait until its time limit (60 s)."""
    os.mkfifo(tmp_path / "gains.h")
    lab = tmp_path / "fifo_lab.c"
    lab.write_text('#include "math.h"\n#include "gains.h"\n' + LAB_BODY)
    r = sim(lab, *board)
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().splitlines()[-1] == ("crslab sim: fifo_lab.c does not compile: fifo_lab.c:2 "
                                                 "includes gains.h, which is a FIFO, not a file")


def test_a_fifo_is_found_through_the_headers_the_lab_includes(tmp_path):
    (tmp_path / "sub").mkdir()
    os.mkfifo(tmp_path / "sub" / "table.h")
    (tmp_path / "sub" / "gains.h").write_text('/* gains */\n\n#include "table.h"\n')
    (tmp_path / "lab.c").write_text('#include <math.h>\n#include "sub/gains.h"\n')
    assert local_includes(tmp_path / "lab.c")[0] == ("sub/gains.h:3 includes table.h, which is a FIFO, "
                                                   "not a file")
    # a header that includes itself is read once; a name outside the folder is the sandbox's
    (tmp_path / "sub" / "gains.h").write_text('#include "gains.h"\n#include "/dev/urandom"\n')
    assert local_includes(tmp_path / "lab.c")[0] is None


def test_a_compiler_out_of_time_is_killed_with_every_process_it_started(tmp_path):
    """A compiler driver's children (cc1, as) are in its process group: all of it is killed."""
    pid_file = tmp_path / "grandchild.pid"
    r = run_compile(["sh", "-c", f"{sleeper(pid_file)}; wait"], env={"PATH": os.environ["PATH"]},
                    timeout_s=2.0)
    assert r.timed_out and r.returncode < 0
    wait_gone_child(pid_file)


def test_a_compiler_that_ends_leaves_no_process_of_its_group_behind(tmp_path):
    """A compiler that exits while a child of its group runs on (its output elsewhere, so the wait
    for the compiler's output ends): the child is killed with the group when the wait ends, not
    left to run beside crslab (a serve session or a grade job lives on after its build)."""
    pid_file = tmp_path / "grandchild.pid"
    script = f"{sleeper(pid_file, quiet=True)}; exit 0"
    r = run_compile(["sh", "-c", script], env={"PATH": os.environ["PATH"]}, timeout_s=20.0)
    assert not r.timed_out and r.returncode == 0
    wait_gone_child(pid_file)


def sleeper(pid_file: Path, quiet: bool = False) -> str:
    """A shell line that starts a child sleeping 600 s and writes its id and its start time (field
    22 of /proc/PID/stat: ids wrap, and a new process may have this one's id by the time it is
    looked at; the pair names one process) to ``pid_file``; ``quiet``: the child's output goes
    elsewhere, so waiting for the compiler's output does not wait for it."""
    out = " >/dev/null 2>&1" if quiet else ""
    return f"sleep 600{out} & echo $! $(cut -d ' ' -f 22 /proc/$!/stat) > {pid_file}"


def wait_gone_child(pid_file: Path) -> None:
    """The child :func:`sleeper` wrote down ends: SIGKILL was sent to its group, and it ends as soon
    as the kernel delivers it (left alone, it would still sleep for 600 s)."""
    child, started = (int(x) for x in pid_file.read_text().split())
    wait_until(lambda: process_state(child, started) in ("gone", "Z"),
               f"the end of the compiler's child {child} (it outlived the compiler)", timeout_s=10.0)


def process_state(pid: int, started: int) -> str:
    """The state letter of the process ``pid`` that started at ``started`` (clock ticks after boot),
    or "gone" when no such process is left (its id free, or another process's now).

    >>> process_state(os.getpid(), int(Path("/proc/self/stat").read_text().rsplit(")", 1)[1].split()[19]))
    'R'
    >>> process_state(os.getpid(), 0)
    'gone'
    """
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except FileNotFoundError:
        return "gone"
    # after the command's closing parenthesis: field 3 (state) first, field 22 (start time) at 19
    return fields[0] if int(fields[19]) == started else "gone"


def test_a_compilers_address_space_is_bounded(tmp_path):
    grab = "x = bytearray(2 * 1024 ** 3); print('got it')"
    r = run_compile([sys.executable, "-c", grab], env={}, memory_bytes=1024 ** 3)
    assert r.returncode != 0 and "MemoryError" in r.stderr and not r.timed_out
    r = run_compile([sys.executable, "-c", grab.replace("2 *", "0 *")], env={}, memory_bytes=1024 ** 3)
    assert r.returncode == 0


def test_an_image_over_8_mb_is_refused_and_not_kept(tmp_path):
    """``.fill`` puts 9 MB of bytes into the shared object (the source's globals, which the board's
    memory check reads, are small)."""
    lab = tmp_path / "fill_lab.c"
    lab.write_text('__asm__(".section .rodata.big,\\"a\\"\\n.fill 9000000,1,0x41\\n.text\\n");\n' + LAB_BODY)
    cache = tmp_path / "cache"
    r = sim(lab, "--native", cache=cache)
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().splitlines()[-1] == (
        "crslab sim: fill_lab.c does not compile: its image is 9 MB, more than the 8 MB crslab builds "
        "(the F28335 has 512 KB of flash)")
    sizes = [p.stat().st_size for p in cache.rglob("*") if p.is_file()]
    assert sizes and max(sizes) < IMAGE_CAP_BYTES


def test_a_firmware_whose_data_outgrows_the_boards_memory_does_not_link(tmp_path):
    """The same 9 MB as WebAssembly data: the firmware's memory is at most 1 MiB, so the linker
    refuses it and the image is never written."""
    lab = tmp_path / "fill_lab.c"
    lab.write_text('__asm__(".section .rodata.big,\\"\\",@\\n.globl big\\nbig:\\n.fill 9000000,1,0x41\\n'
                   '.size big, 9000000\\n");\nextern const char big[];\n'
                   + LAB_BODY.replace("*tau1 = 0;", "*tau1 = big[(int)theta1motor];"))
    r = sim(lab)
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().splitlines()[-1] == (
        "crslab sim: fill_lab.c does not fit the board: it needs 8,896 KB of memory, crslab's board gives "
        "a lab 1,024 KB (stack, data and heap)")
