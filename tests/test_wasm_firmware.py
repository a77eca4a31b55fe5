"""The lab as a WebAssembly firmware on crslab's board: it prints what the native build prints,
byte for byte, for every lab file the tests have whose arithmetic and memory the board's widths and
layout leave alone (the others print the same to the digits their widths keep, or with the arm one
encoder count apart where float and double round to two sides of a count's edge); it imports nothing
but the board's functions and the C library's WASI calls; its memory is the board's and no more;
what it costs is counted in instructions, the same on every machine."""

import ast
import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from crslab.framework_facts import ENCODER_COUNTS_PER_REV
from crslab.lab.build import build_lab
from crslab.lab.firmware import IR_MOVER_MODULES, MEMORY_BYTES, STACK_BYTES, ir_mover_text
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
    "lab1_own_ik.c": "its inverse kinematics in double",
    "lab3_inverse_dynamics.c": "its dynamics in double",
}
COUNT_RAD = 2 * math.pi / ENCODER_COUNTS_PER_REV
"""One encoder count: where float and double round a torque to the two sides of a count's edge, the
arm stands a count apart at the next tick, and a lab's feedback turns that count into torque."""
ONE_COUNT = {
    # lab -> what one count of joint 2 behind changes in its PD's joint-2 acceleration a[1] (rad/s^2):
    # Kp * count + Kd * count / 3 ms (its speed is a 3-sample mean of 1 ms differences); then tau2 moves by
    # p_mass[0] * that less its viscous friction's Vpos[1] * count / 3 ms (0.0346) and tau3 by
    # p_mass[2] * |sin(th3 - th2)| * that (its coupling term)
    "lab3_inverse_dynamics.c": 2500 * COUNT_RAD + 100 * COUNT_RAD / 0.003,
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
    if lab.name not in ONE_COUNT:
        assert comparison.ok, comparison.report()
        return
    # lab3_inverse_dynamics prints theta1-3 (rad) and tau2, tau3: where a line differs past the digits,
    # joint 2 stood one count apart (to its printed 5 decimals), the others not, and tau2 and tau3 moved by
    # what one count makes them
    da = ONE_COUNT[lab.name]
    for diff in comparison.diffs:
        assert diff.expected is not None and diff.got is not None, comparison.report()
        want, have = ([float(x) for x in line.text.split()] for line in (diff.expected, diff.got))
        assert abs(abs(have[1] - want[1]) - COUNT_RAD) <= 1e-5, comparison.report()
        assert abs(have[0] - want[0]) <= 1e-5 and abs(have[2] - want[2]) <= 1e-5, comparison.report()
        dtau2 = 0.0466 * da - 0.2500 * COUNT_RAD / 0.003
        dtau3 = 0.0284 * abs(math.sin(want[2] - want[1])) * da
        assert abs(abs(have[3] - want[3]) - dtau2) <= 0.1 * dtau2, comparison.report()
        assert abs(abs(have[4] - want[4]) - dtau3) <= 0.1 * dtau3, comparison.report()
    assert len(comparison.diffs) <= 2, comparison.report()  # a count's edge, not a drift


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




def test_every_module_that_moves_the_ir_is_part_of_the_builds_name():
    """A build's name holds the text of the modules that make its IR (a cached build from an older
    crslab is not reused): crslab/lab/c28x_ir.py and every module of crslab.lab it imports,
    directly or not, read here from their import lines; each one's text is in the name's part."""
    folder = Path(__file__).resolve().parents[1] / "crslab" / "lab"
    found, todo = set(), ["c28x_ir.py"]
    while todo:
        name = todo.pop()
        found.add(name)
        for node in ast.walk(ast.parse((folder / name).read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("crslab.lab."):
                todo.append(node.module.removeprefix("crslab.lab.") + ".py")
    assert found == set(IR_MOVER_MODULES)
    assert all((folder / name).read_bytes() in ir_mover_text() for name in found)
