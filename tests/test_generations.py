"""A framework generation is one row of ``csrc/port/generations.c``, read by the board, the
firmware and Python (``crslab.generations``); an id or a name no row has fails loudly on every
side; and a third generation is one more row and its header: a copy of Gen B with another
serial_printf buffer, built into a copy of crslab, runs a lab whose lines that buffer decides."""

import dataclasses
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from crslab._core import ffi, lib

from crslab.generations import GEN_A, GEN_B, GENERATIONS, NEWEST, UnknownGeneration, detect, named, of
from crslab.run.api import make_config
from crslab.run.board_run import BoardRun, RunError
from crslab.sinks.memory import MemorySink
from crslab.sinks.sink import FanOut
from crslab.starters import starter_text

ROOT = Path(__file__).resolve().parents[1]


def test_each_row_holds_its_generations_facts():
    # docs/framework.md sections 2, 5, 6, 8 and 9, number by number
    assert [(g.name, g.id) for g in GENERATIONS] == [("A", 1), ("B", 2)] and NEWEST == GEN_B
    assert (GEN_A.include, GEN_B.include) == ("coecsl.h", "F28335Serial.h")
    assert (GEN_A.printf_buffer_chars, GEN_A.tx_ring_chars, GEN_A.scib_tx_ring_chars,
            GEN_A.scic_tx_ring_chars) == (2048, 2048, 2048, 2048)
    assert (GEN_B.printf_buffer_chars, GEN_B.tx_ring_chars, GEN_B.scib_tx_ring_chars,
            GEN_B.scic_tx_ring_chars) == (136, 136, 136, 2000)
    assert (GEN_A.print_call, GEN_B.print_call) == ("SWI_post(&SWI_printf)", "UARTprint = 1")
    assert (GEN_A.default_motor_board, GEN_B.default_motor_board) == ("none", "piccolo")
    assert GEN_A.matlab_lock and not GEN_B.matlab_lock
    assert GEN_A.section_origins == {".ebss": 0x9000, ".my_vars": 0xC816, ".my_arrs": 0xC4C0}
    assert GEN_B.section_origins == {".ebss": 0x9000, ".my_vars": 0xD000, ".my_arrs": 0xE000}
    assert (GEN_A.framework_object, GEN_B.framework_object) == ("user_CRSRobot.obj", "F28335Serial.obj")
    for g in GENERATIONS:
        assert lib.crs_generation_problem(lib.crs_generation_of(g.id)) == ffi.NULL, g.name
        assert re.search(f'#include [<"]{re.escape(g.include)}[>"]', g.starter_includes), g.name


def test_a_lab_is_of_the_first_generation_whose_header_it_includes():
    assert detect('#include "math.h"\n#include "F28335Serial.h"\n') == GEN_B
    assert detect("#include <tistdtypes.h>\n#include <coecsl.h>\n") == GEN_A
    assert detect('#include <coecsl.h>\n#include "F28335Serial.h"\n') == GEN_A  # as crslab always has
    assert detect('// #include "F28335Serial.h" is a comment\nint x;') == GEN_A  # no header: the first row
    for g in GENERATIONS:
        assert detect(starter_text("lab2", g.name)) == g


def test_an_unknown_generation_fails_loudly_in_python():
    with pytest.raises(UnknownGeneration, match=r"no framework generation 3 \(it knows A \(1\), B \(2\)\)"):
        of(3)
    with pytest.raises(UnknownGeneration, match="no framework generation 'C'"):
        named("C")
    with pytest.raises(UnknownGeneration, match="no framework generation 'C'"):
        starter_text("lab1", "C")


@pytest.mark.parametrize("native", [False, True], ids=["wasm", "native"])
def test_the_board_refuses_a_generation_no_row_has(native):
    config = make_config(None, "hands_off", native=native)
    build = config.build
    unknown = dataclasses.replace(config, build=dataclasses.replace(build, generation=dataclasses.replace(
        build.generation, id=9)))
    with pytest.raises(RunError, match=r"knows no framework generation 9 \(it knows A \(1\), B \(2\)\)"):
        with BoardRun(unknown) as s:
            s.run(100, FanOut([MemorySink()]))


# ---- a third generation -------------------------------------------------------------------------

GEN_C_HEADER = "F28335SerialC.h"
GEN_C_BUFFER = 256

LONG_LINE_LAB = """/* Test lab, Gen B style: on its first call prints one line of LINE_CHARS characters, the
 * line end included, then its call count every 100 ms. */
#include "math.h"
#include "@HEADER@"

#define LINE_CHARS @CHARS@

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;
long mycount = 0;
char dump[LINE_CHARS - 1];

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 100) == 0) {
        UARTprint = 1;
    }
    mycount++;
}

void printing(void)
{
    int i;
    if (mycount == 1) {
        for (i = 0; i < LINE_CHARS - 2; i++) {
            dump[i] = (char)('a' + i % 26);
        }
        dump[LINE_CHARS - 2] = 0;
        serial_printf(&SerialA, "%s\\n\\r", dump);
    } else {
        serial_printf(&SerialA, "call %ld\\n\\r", mycount - 1);
    }
}
"""


def add_gen_c_row(rows: str) -> str:
    """generations.c with one more row after Gen B's: a copy of it with another id, name, header
    and serial_printf buffer (and SerialA's ring, as large)."""
    [b_row] = re.findall(r"\n    \{\n        \.id = CRS_GEN_B,\n.*?\n    \},\n", rows, re.DOTALL)
    c_row = b_row
    for old, new in ((".id = CRS_GEN_B,", ".id = 3,"), ('.name = "B",', '.name = "C",'),
                     ('Gen B \\"me446 starter\\"', 'Gen C \\"me446 starter, larger buffer\\"'),
                     (".printf_buffer_chars = 136,", f".printf_buffer_chars = {GEN_C_BUFFER},"),
                     (".tx_ring_chars = 136,", f".tx_ring_chars = {GEN_C_BUFFER},")):
        assert c_row.count(old) == 1, old
        c_row = c_row.replace(old, new)
    assert c_row.count("F28335Serial.h") == 2  # its include and its starting file's
    return rows.replace(b_row, b_row + c_row.replace("F28335Serial.h", GEN_C_HEADER))


@pytest.fixture(scope="module")
def with_gen_c(tmp_path_factory):
    """A copy of crslab (package, C and model) whose table has the third row and whose board
    headers have its header, with its C core built; returns a runner of ``python -m crslab``
    (or of ``python -c`` code) in that copy, and a folder for its labs."""
    copy = tmp_path_factory.mktemp("gen_c") / "crslab-checkout"
    shutil.copytree(ROOT / "crslab", copy / "crslab", ignore=shutil.ignore_patterns("_core*", "__pycache__"))
    shutil.copytree(ROOT / "csrc", copy / "csrc", ignore=shutil.ignore_patterns("*.o", "__pycache__"))
    shutil.copytree(ROOT / "models", copy / "models")
    table = copy / "csrc" / "port" / "generations.c"
    table.write_text(add_gen_c_row(table.read_text()))
    include = copy / "csrc" / "firmware" / "include"
    b_header = (include / "F28335Serial.h").read_text()
    (include / GEN_C_HEADER).write_text(b_header.replace("CRSLAB_F28335SERIAL_H", "CRSLAB_F28335SERIALC_H"))
    # the C core, as setup.py builds it (cffi_build.py names its sources relative to the folder)
    built = subprocess.run([sys.executable, "csrc/cffi_build.py"], cwd=copy, capture_output=True, text=True,
                           timeout=600)
    assert built.returncode == 0, built.stdout[-2000:] + built.stderr[-2000:]
    shutil.copy2(ROOT / "pyproject.toml", copy / "pyproject.toml")  # marks the copy a checkout (resources)
    env = dict(os.environ, PYTHONPATH=str(copy))
    labs = tmp_path_factory.mktemp("gen_c_labs")

    def run(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, *args], cwd=labs, env=env, capture_output=True, timeout=600)

    return run, labs


def long_line_lab(folder: Path, header: str, chars: int) -> Path:
    lab = folder / f"long_line_{Path(header).stem}_{chars}.c"
    lab.write_text(LONG_LINE_LAB.replace("@HEADER@", header).replace("@CHARS@", str(chars)))
    return lab


def sim(run, lab: Path, *more: str) -> tuple[subprocess.CompletedProcess, bytes]:
    """``crslab sim`` for 250 ms from the first lab() call; its result and its transcript's bytes."""
    transcript = lab.with_suffix(".transcript")
    transcript.unlink(missing_ok=True)
    done = run("-m", "crslab", "sim", "--lab", str(lab), "--scenario", "hands_off", "--no-startup-delay",
               "--duration", "0.25", "--quiet", "--no-stdin", "--transcript", str(transcript), *more)
    return done, transcript.read_bytes() if transcript.exists() else b""


def test_the_third_row_is_read_by_python(with_gen_c):
    run, _ = with_gen_c
    r = run("-c", "import json, crslab.generations as g; print(json.dumps([g.GEN_B.__dict__, "
            f"g.NEWEST.__dict__, g.__file__, g.detect('#include \"{GEN_C_HEADER}\"').name]))")
    assert r.returncode == 0, r.stderr.decode()
    b, c, where, detected = json.loads(r.stdout)
    assert Path(where).parts[-3] == "crslab-checkout"  # the copy's package, not the checkout's
    assert detected == "C"
    # a copy of B in everything but its id, name, title, header and SerialA's buffer and ring
    differ = {k for k in b if b[k] != c[k]}
    assert differ == {"id", "name", "title", "include", "starter_includes", "printf_buffer_chars",
                      "tx_ring_chars"}
    assert (c["id"], c["name"], c["include"]) == (3, "C", GEN_C_HEADER)
    assert c["printf_buffer_chars"] == c["tx_ring_chars"] == GEN_C_BUFFER


def test_a_lab_of_the_third_generation_prints_to_its_own_buffer_size(with_gen_c):
    run, labs = with_gen_c
    dump = bytes(ord("a") + i % 26 for i in range(GEN_C_BUFFER - 3))
    # GEN_C_BUFFER - 1 characters and the NUL fit Gen C's buffer, and its ring holds all of them
    for native in ((), ("--native",)):
        fits, printed = sim(run, long_line_lab(labs, GEN_C_HEADER, GEN_C_BUFFER - 1), *native)
        assert fits.returncode == 0, fits.stderr.decode()
        assert printed == dump + b"\n\rcall 100\n\rcall 200\n\r"
        assert b"dropped" not in fits.stderr
    # one more overflows it: the run stops at the first line, naming Gen C's buffer
    over, printed = sim(run, long_line_lab(labs, GEN_C_HEADER, GEN_C_BUFFER))
    assert over.returncode == 3 and printed == b""
    said = f"formatted {GEN_C_BUFFER} characters; the board's {GEN_C_BUFFER}-byte serial_printf buffer"
    assert said.encode() in over.stderr
    # the same line in Gen B, the row Gen C was copied from, overflows Gen B's 136 bytes
    as_b, printed = sim(run, long_line_lab(labs, "F28335Serial.h", GEN_C_BUFFER - 1))
    assert as_b.returncode == 3 and printed == b""
    assert b"the board's 136-byte serial_printf buffer" in as_b.stderr


def test_first_lab_says_what_an_over_long_line_does():
    """docs/first-lab.md section 5 says what the test above shows a line over the buffer does (the
    run stops, exit 3), not that it only warns."""
    text = (Path(__file__).resolve().parents[1] / "docs" / "first-lab.md").read_text()
    section = text.split("## 5. Printing", 1)[1].split("\n## ", 1)[0]
    said = " ".join(section.split())
    assert "(Gen B: 135 characters and the terminating NUL in 136 bytes) stops the run at that line, exit " \
           "status 3 (crashed)" in said
    assert "warning" not in said.split("A line longer")[1].split(".")[0]


def test_crslab_new_writes_a_starting_file_of_the_third_generation(with_gen_c):
    run, labs = with_gen_c
    made = run("-m", "crslab", "new", "lab1", "lab1_c.c")  # the newest row is the default
    assert made.returncode == 0, made.stderr.decode()
    text = (labs / "lab1_c.c").read_text()
    assert f'#include "{GEN_C_HEADER}"' in text and "UARTprint = 1;" in text
    assert text.startswith('/* Lab 1 (kinematics): a starting file for the Gen C "me446 starter, larger')
    ran, printed = sim(run, labs / "lab1_c.c")
    assert ran.returncode == 0, ran.stderr.decode()
    assert printed.startswith(b"0.00 ") and printed.count(b"\n\r") == 3  # its first call prints 3 lines
