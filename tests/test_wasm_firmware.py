"""The lab as a WebAssembly firmware on crslab's board: it prints what the native build prints,
byte for byte, for every lab file the tests have whose arithmetic and memory the board's widths and
layout leave alone (the others print the same to the digits their widths keep); it imports nothing
but the board's functions and the C library's WASI calls; its memory is the board's and no more;
what it costs is counted in instructions, the same on every machine."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from crslab.lab.build import build_lab
from crslab.lab.firmware import MEMORY_BYTES, STACK_BYTES
from crslab.regress.compare import compare_lines
from crslab.run.api import simulate

ROOT = Path(__file__).resolve().parents[1]
LABS = ROOT / "tests" / "labs"
# every lab file that builds and runs to its end (the faulty and hostile ones have tests of their own)
COURSE_LABS = sorted([*LABS.glob("*.c"), *LABS.glob("*.cpp"), *(ROOT / "csrc" / "labs").glob("*.c"),
                      LABS / "grade_classes" / "reference.c"])
STOPS = {"does_not_compile.c", "crash_after_5s.c", "hang_after_5s.c", "busy_wait_global_gen_b.c"}
BOARD_WIDTHS = {
    # lab -> why the WebAssembly board, which compiles the lab with the C28x's widths and lays its globals
    # out as the TI linker does, prints other digits than a native build (the host's widths and layout)
    "lab1_kinematics.c": "its kinematics (crslab's C) in double, a 32-bit float on the board",
    "lab2_tracking.c": "its trajectory (crslab's C) in double",
    "lab1_own_ik.c": "its inverse kinematics in double",
    "lab3_inverse_dynamics.c": "its dynamics in double",
}
OTHERWISE = {
    # lab -> what the board's widths or layout change, and where that is tested
    "implicit_decls_gen_b.c": "an undeclared malloc's pointer, lost: tests/test_lab_definitions.py",
    "template_off_by_one_gen_a.c": "a store past an array's end meets the board's neighbour: test_c28x_board",
    "double_digits_gen_b.c": "it prints double arithmetic to more digits than a float holds: test_c28x_board",
}
INSPECT = """
import json, sys, wasmtime
module = wasmtime.Module.from_file(wasmtime.Engine(), sys.argv[1])
memory = [e.type.limits for e in module.exports if e.name == "memory"][0]
print(json.dumps({"imports": [[i.module, i.name] for i in module.imports], "memory_max": memory.max,
                  "exports": [e.name for e in module.exports]}))
"""
"""Read with wasmtime's own Python API, in a process of its own (wasmtime's signal handlers stay
out of the test process, whose forked workers run firmware)."""


@pytest.mark.parametrize("lab", [p for p in COURSE_LABS if p.name not in STOPS | set(OTHERWISE)],
                         ids=lambda p: p.name)
def test_every_lab_prints_the_same_bytes_as_firmware_and_natively(lab):
    wasm = simulate(lab, "tour", duration_s=12.0)
    native = simulate(lab, "tour", duration_s=12.0, native=True)
    assert wasm.status == native.status, (wasm.message, native.message)  # ok, or the same overflow
    assert wasm.message == native.message
    assert [t for t, _ in wasm.calls] == [t for t, _ in native.calls]  # each call at the same tick
    assert wasm.stats.cost_unit != native.stats.cost_unit  # they did run on the two boards
    if lab.name not in BOARD_WIDTHS:
        assert wasm.transcript == native.transcript  # byte for byte
        return
    # the same lines, each number within a few counts of its last printed digit: float against double
    got, host = (r.transcript.decode().split("\n\r") for r in (wasm, native))
    assert wasm.transcript != native.transcript, BOARD_WIDTHS[lab.name]
    comparison = compare_lines(host, got, abs_tol=0.03, rel_tol=1e-4)
    assert comparison.ok, comparison.report()


def test_the_firmware_imports_only_the_boards_functions_and_its_memory_is_the_boards():
    build = build_lab(ROOT / "csrc" / "labs" / "lab1_kinematics.c")
    assert not build.native and build.image.suffix == ".wasm"
    r = subprocess.run([sys.executable, "-c", INSPECT, str(build.image)], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    module = json.loads(r.stdout)
    imports = {tuple(i) for i in module["imports"]}
    assert {m for m, _ in imports} <= {"board", "wasi_snapshot_preview1"}
    assert ("board", "serial_send") in imports
    assert module["memory_max"] * 65536 == MEMORY_BYTES  # its heap grows to the board's limit, no more
    exports = set(module["exports"])
    assert {"crs_fw_start", "crs_fw_lab", "crs_fw_printing", "whattoprint", "mycount"} <= exports


def test_the_stack_comes_first_so_a_runaway_recursion_runs_off_the_memory(tmp_path):
    lab = tmp_path / "deep.c"
    lab.write_text('#include <coecsl.h>\nint depth(int n) { volatile char pad[1024]; pad[0] = (char)n;\n'
                   '  return n > 100000 ? pad[0] : depth(n + 1) + pad[0]; }\nint where;\n'
                   "void lab(float a, float b, float c, float *t1, float *t2, float *t3, int e)\n"
                   "{ *t1 = 0; if (e == 0) where = depth(0); }\nvoid printing(void) {}\n")
    run = simulate(lab, "hands_off", duration_s=0.01, startup_delay=False)
    # 1 KB a frame: the 64 KB stack at the bottom of memory runs out past its first byte and traps
    assert STACK_BYTES == 64 * 1024
    assert run.status == "crashed" and run.end_tick == 0
    assert run.message.startswith("deep.c overflowed its call stack (runaway recursion) at deep.c:")


@pytest.mark.parametrize("name", ["divide.c", "divide by zero.c"])
def test_a_division_by_zero_is_named_with_its_line_and_what_the_board_would_have_done(tmp_path, name):
    lab = tmp_path / name  # (a name with spaces keeps its line: the build's copy has the same name)
    lab.write_text("#include <coecsl.h>\nint counts = 0, zero = 0, ratio;\n"
                   "void lab(float a, float b, float c, float *t1, float *t2, float *t3, int e)\n{\n"
                   "    *t1 = 0;\n    counts++;\n    if (counts == 3) zero = 0;\n"
                   "    ratio = counts / zero;\n}\nvoid printing(void) {}\n")
    run = simulate(lab, "hands_off", duration_s=0.01, startup_delay=False)
    assert run.status == "crashed"
    assert run.message == (f"{name} divided an integer by zero at {name}:8 in lab() at tick 0 "
                           "(t = 0.000 s); on the C28x an integer division by zero does not stop the board: "
                           "it goes on with an undefined result")
