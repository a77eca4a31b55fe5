"""The lab's globals in the simulated F28335's data memory and the CCS-style map the course's MATLAB
scripts parse: every global parsed from the file, laid out as the TI linker would (16-bit words,
32-bit types at even addresses, .my_arrs / .my_vars / .ebss at their origins), written as a map that
the course's parseMap reads (checked with a second implementation of that parse, written here from
docs/host-tools.md, "The map parseMap reads"). Expected addresses are worked by hand from those rules."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from crslab.cli import main
from crslab.generations import GEN_B
from crslab.host_tools.linker_map import MapError, read_map, write_map
from crslab.lab.build import text_memory
from crslab.lab.c28x_memory import layout, overlapping
from crslab.lab.variables import find_variables

ROOT = Path(__file__).resolve().parents[1]
LABS = ROOT / "tests" / "labs"
GEN_A_LAB, GEN_B_LAB = LABS / "host_tools_gen_a.c", LABS / "host_tools_gen_b.c"


def is_hex(text: str) -> bool:
    """The course's isHex: hex2dec does not throw."""
    try:
        int(text, 16)
    except ValueError:
        return False
    return not text.lower().startswith("0x")


def course_parse_map(text: str) -> list[tuple[str, str, str]]:
    """What the course's parseMap returns, as docs/host-tools.md describes it."""
    lines = re.split(r"\r\n|\r|\n", text)
    arrs = vars_ = None
    i = 0
    while i < len(lines) and "SORTED BY Symbol Address" not in lines[i]:
        words = lines[i].split()
        if arrs is None and ".my_arrs" in lines[i]:
            arrs = (int(words[2], 16), int(words[3], 16))
        if vars_ is None and ".my_vars" in lines[i]:
            vars_ = (int(words[2], 16), int(words[3], 16))
        i += 1
    out: list[tuple[str, str, str]] = []
    for line in lines[i + 1:]:
        words = line.split()
        if not words:
            continue
        assert len(words) >= 2, f"parseMap needs 2 words on every line of the table: {line!r}"
        if not is_hex(words[1]) or len(words) < 3 or is_hex(words[2]):
            continue
        address = int(words[1], 16)
        kind = ("Array Variable" if arrs[0] <= address < arrs[0] + arrs[1] else
                "Float Variable" if vars_[0] <= address < vars_[0] + vars_[1] else None)
        if kind is None:
            continue
        row = (words[2][1:], words[1], kind)
        if out and out[-1][1] == words[1]:
            out[-1] = row
        else:
            out.append(row)
    return out


def test_the_course_parse_written_here_gives_the_documented_result_of_the_minimal_map():
    minimal = """SECTION ALLOCATION MAP

 output                                  attributes/
section   page    origin      length       input sections
--------  ----  ----------  ----------   ----------------
.my_arrs   1    0000a000    000000c8     UNINITIALIZED
                  0000a000    000000c8     mylab.obj (.my_arrs)

.my_vars   1    0000a0c8    00000002     UNINITIALIZED
                  0000a0c8    00000002     mylab.obj (.my_vars)


GLOBAL SYMBOLS: SORTED BY Symbol Address \n
page  address   name
----  -------   ----
1     00009000  _mycount
1     0000a000  _theta1array
1     0000a0c8  _whattoprint

[3 symbols]
"""
    assert course_parse_map(minimal) == [("theta1array", "0000a000", "Array Variable"),
                                         ("whattoprint", "0000a0c8", "Float Variable")]


def test_every_global_is_parsed_with_its_type_dimensions_and_qualifiers():
    src = r"""
    #include "F28335Serial.h"
    #define N 4
    #define ROWS (2)
    typedef float gain_t;
    typedef struct { int a; } pair_t;
    struct state { float x; } st;        /* a struct variable: left out */
    pair_t pairs[3];                     /* of a struct type: left out */
    extern int SIMU_Var1_fromSIMU_16bit; /* declared, defined elsewhere */
    float x_in = 0, y_in = 0.5, *p, grid[ROWS][N];
    static long hidden = 3;
    const float fixed = 1.0f;
    volatile Uint16 flags;
    unsigned long long big;
    long double wide;
    gain_t Kp = 2;
    char name[] = "a;b{";                /* string length: left out */
    int table[] = {1, 2, 3};
    int table[];                         /* the same variable again (a tentative definition) */
    void (*callback)(int);               /* a function pointer: left out */
    float f(float a) { float local = a; return local; }
    #if 0
    float skipped;
    #else
    float kept;
    #endif
    """
    got = [(v.name, v.ctype, v.dims, v.pointer, v.static, v.const) for v in find_variables(src)]
    assert got == [("x_in", "float", (), False, False, False), ("y_in", "float", (), False, False, False),
                   ("p", "float", (), True, False, False), ("grid", "float", (2, 4), False, False, False),
                   ("hidden", "long", (), False, True, False), ("fixed", "float", (), False, False, True),
                   ("flags", "Uint16", (), False, False, False),
                   ("big", "unsigned long long", (), False, False, False),
                   ("wide", "long double", (), False, False, False), ("Kp", "float", (), False, False, False),
                   ("table", "int", (3,), False, False, False), ("kept", "float", (), False, False, False)]
    # a tentative definition first (a header's), then the one with its value: that value, once
    again = find_variables("float offset_Enc3_rad;\nfloat offset_Enc3_rad = 0.25;\nfloat offset_Enc3_rad;\n")
    assert [(v.name, v.initial, v.line) for v in again] == [("offset_Enc3_rad", "0.25", 2)]


def test_gen_a_layout_puts_the_sections_at_the_2019_maps_origins():
    mem = text_memory(GEN_A_LAB.read_text(), "host_tools_gen_a")
    at = {v.name: (v.address, v.words) for v in mem.variables}
    # .ebss from 0x9000: two floats, then mycount (long) at 0x9004, arrayindex (long) at 0x9006,
    # printKp1 (float) 0x9008, the ints printsimu1/2 at 0x900a/b, the four PlotVars from 0x900c
    assert at["offset_Enc2_rad"] == (0x9000, 2) and at["mycount"] == (0x9004, 2)
    assert at["arrayindex"] == (0x9006, 2) and at["printKp1"] == (0x9008, 2)
    assert at["printsimu1"] == (0x900A, 1) and at["printsimu2"] == (0x900B, 1)
    assert at["Simulink_PlotVar1"] == (0x900C, 2) and at["Simulink_PlotVar4"] == (0x9012, 2)
    # then the framework's seven SIMU inputs (the lab only declares two of them extern)
    assert [at[f"SIMU_Var{k}_fromSIMU_16bit"] for k in (1, 7)] == [(0x9014, 1), (0x901A, 1)]
    # .my_arrs at 0xc4c0: theta1array (200 words) then timearray; .my_vars at 0xc816: whattoprint
    # (docs/host-tools.md's worked vectors), Kp1, samples, then the framework's matlabLock
    assert at["theta1array"] == (0xC4C0, 200) and at["timearray"] == (0xC588, 200)
    assert [at[n][0] for n in ("whattoprint", "Kp1", "samples", "matlabLock")] == [
        0xC816, 0xC818, 0xC81A, 0xC81C]
    sections = {s.name: (s.origin, s.length) for s in mem.sections}
    assert sections == {".ebss": (0x9000, 0x1B), ".my_arrs": (0xC4C0, 400), ".my_vars": (0xC816, 8)}
    assert not overlapping(mem)


def test_gen_b_layout_aligns_32_bit_types_and_a_full_section_pushes_the_next():
    src = """#include "F28335Serial.h"
    #pragma DATA_SECTION(mode, ".my_vars")
    int mode;
    #pragma DATA_SECTION(gain, ".my_vars")
    float gain;
    #pragma DATA_SECTION(big, ".my_vars")
    float big[2100];
    #pragma DATA_SECTION(log1, ".my_arrs")
    long log1[2];
    #pragma DATA_SECTION(extra, ".my_extra")
    int extra;
    static int hidden;
    const int fixed = 3;
    char c;
    long after;
    """
    mem = layout(find_variables(src), GEN_B, "big")
    at = {v.name: v.address for v in mem.variables}
    assert at["mode"] == 0xD000 and at["gain"] == 0xD002 and at["big"] == 0xD004  # gain skips 0xd001
    # .my_vars ends at 0xd004 + 4200 = 0xe06c, past .my_arrs' origin 0xe000: .my_arrs moves up
    assert at["log1"] == 0xE06C and at["extra"] == 0xE070  # another section goes after the last
    # .ebss: hidden (static: placed, but no symbol), c, then after at an even address, then the
    # framework's seven inputs up to 0x900a; .econst after it, at an even address
    assert at["hidden"] == 0x9000 and at["c"] == 0x9001 and at["after"] == 0x9002
    assert at["SIMU_Var1_fromSIMU_16bit"] == 0x9004 and at["fixed"] == 0x900C
    assert "matlabLock" not in at  # Gen A's only
    symbols = [v.name for v in mem.symbols()]
    assert "hidden" not in symbols and "fixed" in symbols
    assert not overlapping(mem)


def test_the_map_parses_with_the_course_parser_for_both_generations(tmp_path):
    arr, var = "Array Variable", "Float Variable"
    for lab, mycount, expected in [
        (GEN_A_LAB, 0x9004, [("theta1array", "0000c4c0", arr), ("timearray", "0000c588", arr),
                             ("whattoprint", "0000c816", var), ("Kp1", "0000c818", var),
                             ("samples", "0000c81a", var), ("matlabLock", "0000c81c", var)]),
        (GEN_B_LAB, 0x9006, [("whattoprint", "0000d000", var), ("Kp1", "0000d002", var),
                             ("samples", "0000d004", var), ("mode", "0000d006", var),
                             ("theta1array", "0000e000", arr), ("timearray", "0000e0c8", arr)]),
    ]:
        out = tmp_path / f"{lab.stem}.map"
        assert main(["map", "--lab", str(lab), "-o", str(out)]) == 0
        raw = out.read_bytes()
        assert raw.count(b"\r\n") == raw.count(b"\n")  # CRLF, as CCS writes on Windows
        text = raw.decode()
        assert course_parse_map(text) == expected
        # the pass-1 lines are the section headers (name, page, origin, length)
        assert [line.split()[:4] for line in text.splitlines() if ".my_arrs" in line][0][1] == "1"
        # crslab's own reading of the table (for crslab serial) agrees, and knows every global
        symbols = read_map(text)
        assert {name: f"{address:08x}" for name, address in symbols.items() if name in dict(
            (r[0], 0) for r in expected)} == {r[0]: r[1] for r in expected}
        assert symbols["mycount"] == mycount  # Gen B's UARTprint (one word) comes before it


def test_the_same_file_always_gets_the_same_addresses_and_vars_shows_them(capsys):
    text = GEN_B_LAB.read_text()
    assert write_map(text_memory(text, "x"), "x.c") == write_map(text_memory(text, "x"), "x.c")
    assert main(["vars", "--lab", str(GEN_B_LAB)]) == 0
    rows = {line.split()[0]: line.split()[1] for line in capsys.readouterr().out.splitlines()[1:]}
    assert rows == {"whattoprint": "0000d000", "Kp1": "0000d002", "samples": "0000d004", "mode": "0000d006",
                    "theta1array": "0000e000", "timearray": "0000e0c8"}


def test_map_and_bad_input(tmp_path, capsys):
    assert main(["map", "--lab", str(GEN_A_LAB)]) == 0
    shown = capsys.readouterr().out
    assert "GLOBAL SYMBOLS: SORTED BY Symbol Address" in shown and "\r" not in shown
    assert main(["map", "--lab", str(tmp_path / "missing.c")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no such lab file" in err
    (tmp_path / "a_file").write_text("not a folder")
    assert main(["map", "--lab", str(GEN_A_LAB), "-o", str(tmp_path / "a_file" / "x.map")]) == 2
    assert "cannot write the map" in capsys.readouterr().err
    with pytest.raises(MapError, match="not a TI linker map"):
        read_map("hello")
    r = subprocess.run([sys.executable, "-m", "crslab", "serial", "read", "Kp1", "--map",
                        str(tmp_path / "x.map"), "--port", str(tmp_path / "p")],
                       capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "cannot be read" in r.stderr
