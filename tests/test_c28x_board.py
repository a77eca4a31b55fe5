"""What the board executes, crslab executes (issue 39): labs in the course's style, each run on the
WebAssembly board in ``crslab sim``, ``crslab grade``, ``crslab serve`` and the contest's world, print
what the board's compiler and linker make them print, worked out by hand:

- a busy-wait on an ordinary global inside lab() spins, as the board's unoptimised build does, and
  is stopped with its line named;
- the Lab 1 template's off-by-one stores one past an array of ``.my_arrs`` into the next variable of
  that section, as the TI linker lays them out (``crslab map``), never into an ordinary global;
- an ``int`` counter wraps from 32767 to -32768 on its 32,768th call (16 bits);
- ``double`` arithmetic prints the digits of a 32-bit float.

The firmware's own symbol addresses agree with ``crslab map``'s.
"""

from __future__ import annotations

import csv
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from serve_server import logged_in, roster_server, run_message, serial_of

from crslab.host_tools.linker_map import read_map
from crslab.lab.build import build_lab, text_memory
from crslab.run.api import simulate

LABS = Path(__file__).parent / "labs"
BUSY = LABS / "busy_wait_global_gen_b.c"
TEMPLATE = LABS / "template_off_by_one_gen_a.c"
COUNTER = LABS / "int_counter_wraps_gen_b.c"
DOUBLES = LABS / "double_digits_gen_b.c"
SCENARIO = "hands_off"
DURATION_S = 37.0  # the counter's 32,768th call is at 4.1 s + 32.767 s
BUSY_LINE = next(i for i, line in enumerate(BUSY.read_text().splitlines(), 1) if "while (gave_way" in line)
HUNG = (f"lab() did not return within 2 s at tick 5100 (t = 5.100 s); it was at {BUSY.name}:{BUSY_LINE} "
        "in lab()")


def crslab(*args: object, timeout: float = 600) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout)


def template_expected() -> bytes:
    """What the template lab prints on the board, from its map: theta2array[100] is the word right
    after theta2array's 100 floats (200 words), the first word of theta3array; x is in .ebss."""
    mem = text_memory(TEMPLATE.read_text(), TEMPLATE.stem)
    t2, t3, x = mem.find("theta2array"), mem.find("theta3array"), mem.find("x")
    assert (t2.section, t3.section, x.section) == (".my_arrs", ".my_arrs", ".ebss")
    assert t2.address + 100 * 2 == t3.address  # the store of theta2array[100] lands on theta3array[0]
    # call 0 stores 1000 in theta3array[0]; call 100 (index 100) stores 100 through theta2array[100],
    # then 1100 past the section's end; call 101 (index 0) stores 1101. x stays 20 (Gen A's %f truncates).
    return (b"count 1 x 20.00 theta3array[0] 1000.0\n\r"
            b"count 101 x 20.00 theta3array[0] 100.0\n\r"
            b"count 102 x 20.00 theta3array[0] 1101.0\n\r")


def counter_expected() -> bytes:
    return b"call 1 mycount 1\n\rcall 32767 mycount 32767\n\rcall 32768 mycount -32768\n\r"


def doubles_expected() -> bytes:
    """A 32-bit float's digits (Gen B prints through TI's vsprintf, which rounds the float)."""
    f = np.float32
    third = f(1.0) / f(3.0)
    tenths = f(0.0)
    for _ in range(1000):
        tenths = f(tenths + f(0.1))
    product = f(16777217.0) * f(3.0)
    root = np.sqrt(f(2.0))
    text = f"{float(third):.10f} {float(tenths):.6f} {float(product):.1f} {float(root):.10f}\n\r"
    assert text != f"{1 / 3:.10f} {sum([0.1] * 1000):.6f} {16777217.0 * 3:.1f} {2 ** 0.5:.10f}\n\r"
    return text.encode()


EXPECTED = {TEMPLATE.name: template_expected, COUNTER.name: counter_expected, DOUBLES.name: doubles_expected}


def test_what_each_lab_prints_is_worked_out_by_hand():
    assert template_expected().count(b"\n\r") == 3
    assert doubles_expected() == b"0.3333333433 99.999046 50331648.0 1.4142135382\n\r"


@pytest.fixture(scope="module")
def sims(tmp_path_factory):
    out = tmp_path_factory.mktemp("sim")
    runs = {}
    for lab in (BUSY, TEMPLATE, COUNTER, DOUBLES):
        transcript = out / f"{lab.stem}.txt"
        r = crslab("sim", "--fast", "--quiet", "--lab", lab, "--scenario", SCENARIO, "--duration", DURATION_S,
                   "--transcript", transcript)
        runs[lab.name] = (r, transcript.read_bytes() if transcript.exists() else b"")
    return runs


def test_sim_a_busy_wait_on_a_global_hangs_with_its_line_named(sims):
    r, transcript = sims[BUSY.name]
    assert r.returncode == 4, r.stderr
    assert r.stderr.strip().splitlines()[-1] == f"crslab sim: {BUSY.name} hung: {HUNG}"
    assert transcript == b"0.00\n\r0.00\n\r"  # printed after calls 0 and 500; call 1000 never returns


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_sim_prints_what_the_board_prints(sims, name):
    r, transcript = sims[name]
    assert r.returncode == 0, r.stderr
    assert transcript == EXPECTED[name]()


def test_grade_classes_and_records_the_same(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    for lab in (BUSY, TEMPLATE, COUNTER, DOUBLES):
        shutil.copy(lab, subs / lab.name)
    out = tmp_path / "out"
    r = crslab("grade", subs, "--reference", COUNTER, "--scenario", SCENARIO, "--duration", DURATION_S,
               "--deadline", "2", "--out", out, "--jobs", "2", "--no-c28x-check")
    assert r.returncode == 1, r.stderr
    with (out / "grades.csv").open() as f:
        rows = {row["submission"]: row for row in csv.DictReader(f)}
    assert {k: v["result"] for k, v in rows.items()} == {
        BUSY.name: "hung", TEMPLATE.name: "mismatch", COUNTER.name: "pass", DOUBLES.name: "mismatch"}
    assert rows[BUSY.name]["detail"] == f"{BUSY.name} hung: {HUNG}"
    for name, expected in EXPECTED.items():
        assert (out / "transcripts" / f"{name}.txt").read_bytes() == expected(), name


@pytest.fixture(scope="module")
def alice(tmp_path_factory):
    for server in roster_server(tmp_path_factory):
        yield from logged_in(server, "alice")


def test_serve_runs_them_as_the_board_does(alice):
    alice.send(run_message(BUSY, name=BUSY.name, duration=6.0, scenario={"name": SCENARIO}))
    ended = alice.until("ended")[-1]
    # a shared server ends the spinning call at its share of instructions, not after 2 s: the same
    # call, named at the same line
    assert ended["status"] == "hung", ended
    shared = f"{BUSY.name} is too slow for a shared server: lab() cost more than "
    assert ended["message"].startswith(shared), ended
    assert (f" in one call at tick 5100 (t = 5.100 s); it was at {BUSY.name}:{BUSY_LINE} in lab();"
            in ended["message"]), ended
    for name, expected in EXPECTED.items():
        alice.send(run_message(LABS / name, name=name, duration=DURATION_S, scenario={"name": SCENARIO}))
        got = alice.until("ended")
        assert got[-1]["status"] == "ok", got[-1]
        assert b"".join(text for _, text in serial_of(got)) == expected(), name


def test_the_contest_world_runs_them_as_the_board_does():
    r = crslab("contest", "--lab", BUSY, "--duration", 6, "--json")
    assert r.returncode == 4, r.stderr  # never scored as done
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("crslab contest: ") and last.endswith(f"{BUSY.name} hung: {HUNG}"), last
    for name, expected in EXPECTED.items():
        run = simulate(LABS / name, SCENARIO, duration_s=DURATION_S, world="contest")
        assert run.status == "ok" and run.transcript == expected(), (name, run.message)


def test_the_firmwares_own_addresses_are_crslab_maps(tmp_path):
    """Every global of the lab (and the framework's own in the map) sits in the firmware at twice its
    word offset in the map from one base: the block that stands for the board's data memory."""
    text = TEMPLATE.read_text().replace("long arrayindex = 0;",
                                        "long arrayindex = 0;\nstatic int hidden = 1;")
    lab = tmp_path / "template.c"
    lab.write_text(text)
    map_file = tmp_path / "template.map"
    r = crslab("map", "--lab", lab, "-o", map_file)
    assert r.returncode == 0, r.stderr
    board = read_map(map_file.read_text())
    build = build_lab(lab)
    addresses = firmware_addresses(build.image)
    assert set(board) <= set(addresses), set(board) - set(addresses)  # every symbol of the map is exported...
    origin = min(board.values())
    bases = {name: addresses[name] - 2 * (board[name] - origin) for name in board}
    assert len(set(bases.values())) == 1, bases  # ...at its place in one block
    assert "SIMU_Var7_fromSIMU_16bit" in board and "theta3array" in board and "hidden" not in board


def firmware_addresses(image: Path) -> dict[str, int]:
    """The address each exported global of the module holds, read by instantiating it (wasmtime, in a
    process of its own) with the board's imports stubbed."""
    script = (
        "import json, sys, wasmtime\nengine = wasmtime.Engine()\nstore = wasmtime.Store(engine)\n"
        "module = wasmtime.Module.from_file(engine, sys.argv[1])\nlinker = wasmtime.Linker(engine)\n"
        "linker.define_wasi()\nstore.set_wasi(wasmtime.WasiConfig())\n"
        "i32 = wasmtime.ValType.i32()\n"
        "linker.define_func('board', 'fault', wasmtime.FuncType([i32, i32], []), lambda k, l: None)\n"
        "linker.define_func('board', 'serial_send', wasmtime.FuncType([i32, i32, i32], [i32]),\n"
        "                   lambda p, c, n: n)\n"
        "exports = linker.instantiate(store, module).exports(store)\n"
        "print(json.dumps({e.name: exports[e.name].value(store) for e in module.exports\n"
        "                  if isinstance(e.type, wasmtime.GlobalType)}))\n")
    r = subprocess.run([sys.executable, "-c", script, str(image)], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def test_signed_overflow_is_computed_not_assumed_away(tmp_path):
    """Built with the optimisation off, as on the board: ``count + 1 > count`` is computed, and at
    32767 the 16-bit sum is -32768 (a compiler allowed to assume no overflow makes it always 1)."""
    lab = tmp_path / "overflow.c"
    lab.write_text('#include "F28335Serial.h"\nint UARTprint = 0;\nint count = 32766;\nint step = 0;\n'
                   "int bigger[2];\n"
                   "void lab(float a, float b, float c, float *t1, float *t2, float *t3, int e)\n{\n"
                   "    if (step < 2) {\n        bigger[step] = count + 1 > count;\n"
                   "        count = count + 1;\n        step = step + 1;\n        UARTprint = 1;\n    }\n}\n"
                   'void printing(void)\n{\n    serial_printf(&SerialA, "%d %d %d\\n\\r", '
                   "bigger[0], bigger[1], count);\n}\n")
    run = simulate(lab, SCENARIO, duration_s=4.103)
    assert run.status == "ok", run.message
    # 32766 + 1 > 32766; then 32767 + 1 is -32768, not more than 32767
    assert run.transcript == b"1 0 32767\n\r1 0 -32768\n\r"


ARITHMETIC = """#include "F28335Serial.h"
int UARTprint = 0;
int zero = 0, minus1 = -1, most = -32768, seven = 7, done = 0;
long lzero = 0, lminus1 = -1, lmost = -2147483647L - 1, big = 100000L;
unsigned int uzero = 0;
unsigned long ulzero = 0;
float fzero = 0.0, huge = 1e20, over = 40000.0;
int q[6], r[4], flags[3], to16[5];
long lq[4], lr[2], to32;
int __crs_c28x_sdiv_i16(int a, int b) { return 42; } /* a lab's own names cannot take crslab's */
int __crs_c28x_ram = 5;
void lab(float a, float b, float c, float *t1, float *t2, float *t3, int e)
{
    if (done) return;
    q[0] = seven / zero;  q[1] = -seven / zero;  q[2] = most / minus1;
    q[3] = seven / 2;     q[4] = -seven / 2;     q[5] = seven / 0;
    r[0] = seven % zero;  r[1] = -seven % zero;  r[2] = most % minus1;  r[3] = -seven % 2;
    lq[0] = big / lzero;  lq[1] = -big / lzero;  lq[2] = lmost / lminus1;  lq[3] = lmost / -1L;
    lr[0] = big % lzero;  lr[1] = lmost % lminus1;
    flags[0] = (7u / uzero == 65535u) + 2 * (7u % uzero == 7u);
    flags[1] = (5UL / ulzero == 4294967295UL) + 2 * (5UL % ulzero == 5UL);
    to16[0] = (int)(1.0 / fzero);  to16[1] = (int)(-huge);  to16[2] = (int)over;
    to16[3] = (int)(fzero / fzero);  to16[4] = (int)-2.7;
    flags[2] = ((unsigned int)huge == 65535u) + 2 * ((unsigned int)(-3.0 * over) == 0u);
    to32 = (long)(1.0 / fzero);
    done = 1;
    UARTprint = 1;
}
void printing(void)
{
    serial_printf(&SerialA, "%d %d %d %d %d %d\\n\\r", q[0], q[1], q[2], q[3], q[4], q[5]);
    serial_printf(&SerialA, "%d %d %d %d\\n\\r", r[0], r[1], r[2], r[3]);
    serial_printf(&SerialA, "%ld %ld %ld %ld %ld %ld\\n\\r", lq[0], lq[1], lq[2], lq[3], lr[0], lr[1]);
    serial_printf(&SerialA, "%d %d %d\\n\\r", flags[0], flags[1], flags[2]);
    serial_printf(&SerialA, "%d %d %d %d %d %ld\\n\\r", to16[0], to16[1], to16[2], to16[3], to16[4], to32);
}
"""


def test_integer_division_by_zero_and_16_bit_conversions_give_what_the_c28x_computes(tmp_path):
    """The C28x's division is a SUBCU loop on the magnitudes (crslab/lab/c28x_arithmetic.py): by zero
    the quotient is all ones (-1, negated to 1 for a negative dividend; 65535 and 4294967295
    unsigned) and the remainder the dividend; the most negative integer by -1 (a variable or a
    literal) is itself, remainder 0.
    WebAssembly would trap on each (the long ones included); ordinary divisions truncate as before.
    A float to an int saturates at 16 bits (F32TOI16; NaN 0), to a long at 32 (F32TOI32); keeping
    the low 16 bits of a 32-bit conversion would give -1, 0 and -25536 for the first three."""
    lab = tmp_path / "arithmetic.c"
    lab.write_text(ARITHMETIC)
    run = simulate(lab, SCENARIO, duration_s=4.101)
    assert run.status == "ok", run.message
    assert run.transcript == (b"-1 1 -32768 3 -3 -1\n\r" b"7 -7 0 -1\n\r"
                              b"-1 1 -2147483648 -2147483648 100000 0\n\r" b"3 3 3\n\r"
                              b"32767 -32768 32767 0 -2 2147483647\n\r")


def test_a_struct_keeps_the_layout_its_sizes_were_computed_for(tmp_path):
    """An int then a float: copied whole (the size the front end computed), indexed in an array and
    measured with sizeof, each the same struct (crslab/lab/c28x_ir.py packs it as AVR lays it out)."""
    lab = tmp_path / "gains.c"
    lab.write_text('#include "F28335Serial.h"\nint UARTprint = 0;\n'
                   "typedef struct { int mode; float gain; } setting;\n"
                   "setting now = {3, 2.5}, saved[2];\nint size = 0;\n"
                   "void lab(float a, float b, float c, float *t1, float *t2, float *t3, int e)\n{\n"
                   "    saved[1] = now;\n    size = sizeof(setting);\n    UARTprint = 1;\n}\n"
                   'void printing(void)\n{\n    serial_printf(&SerialA, "%d %.2f %d\\n\\r", saved[1].mode, '
                   "saved[1].gain, size);\n}\n")
    run = simulate(lab, SCENARIO, duration_s=4.101)
    assert run.status == "ok", run.message
    assert run.transcript == b"3 2.50 6\n\r"  # 2 bytes of int, 4 of float: sizeof counts bytes here
