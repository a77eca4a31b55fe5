"""Every definition of lab() and printing() that C lets the board call runs on both of crslab's
boards (WebAssembly and --native) with the same transcript: six parameters, K&R style; C89 habits
(malloc without <stdlib.h>, a function called before its definition, implicit int) build with a
warning that says what the board does (an undeclared malloc's pointer is lost there, and in the
WebAssembly build, which has the board's widths); a lab counting in `long` prints the same on both
boards, and a native run of it says that `long` is 64 bits there. A refusal names its real cause.

Each lab runs once per board (module scope), on the arm at rest, for 5.2 s (the first lab() call is
at 4.1 s)."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from crslab.lab.build import LabBuildError, build_lab
from crslab.lab.c28x_check import check_lab
from crslab.lab.entry_points import find_definitions, lab_definition, printing_definition

ROOT = Path(__file__).resolve().parents[1]
LABS = ROOT / "tests" / "labs"
NEW_LABS = ["six_params_gen_b.c", "knr_gen_a.c", "implicit_decls_gen_b.c", "long_counts_gen_a.c"]


def sim(lab: Path, *extra: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--scenario",
                           "hands_off", "--fast", "--quiet", "--no-c28x-check", "--duration", "5.2", *extra],
                          capture_output=True, text=True, timeout=600, env=os.environ)


@pytest.fixture(scope="module")
def runs() -> dict[tuple[str, str], subprocess.CompletedProcess]:
    out = {}
    for name in NEW_LABS:
        for board, extra in (("wasm", ()), ("native", ("--native",))):
            out[(name, board)] = sim(LABS / name, *extra)
    return out


LOST_POINTER = "implicit_decls_gen_b.c"
"""Its undeclared malloc() returns a pointer the board's caller reads as a 16-bit int (AL), not the
pointer (XAR4): on the board, and in the WebAssembly build, the ring is not malloc's memory."""


@pytest.mark.parametrize("name", [n for n in NEW_LABS if n != LOST_POINTER])
def test_the_lab_runs_on_both_boards_with_the_same_transcript(runs, name):
    wasm, native = runs[(name, "wasm")], runs[(name, "native")]
    assert wasm.returncode == 0, wasm.stderr
    assert native.returncode == 0, native.stderr
    assert wasm.stdout.strip() and wasm.stdout == native.stdout


def test_a_lab_without_the_error_parameter_gets_its_six_arguments(runs):
    lines = runs[("six_params_gen_b.c", "wasm")].stdout.splitlines()
    assert lines[0] == "call 1: theta1 0.00 deg"  # the arm at rest: joint 1 at 0
    degrees = [float(line.split()[3]) for line in lines]
    # tau1 reaches joint 1: PD towards 0.2 rad = 11.46 deg (Kp 40: there within 250 ms, friction
    # keeps it a little short), never going back
    assert all(b >= a for a, b in zip(degrees, degrees[1:])), degrees
    assert all(9.0 < d < math.degrees(0.2) + 0.5 for d in degrees[1:]), degrees


def test_a_knr_lab_gets_its_float_arguments(runs):
    # K&R float parameters are doubles in the definition: the framework's floats must arrive as such.
    # The arm at rest reads the offsets: -0.42 rad = -24.064 deg, 0.24 rad = 13.751 deg (Gen A's
    # printf truncates to -24.06 and 13.75); the first printing() runs after call 1
    lines = runs[("knr_gen_a.c", "wasm")].stdout.splitlines()
    assert lines[:2] == ["1 0.00 -24.06 13.75", "501 0.00 -24.06 13.75"]


def test_c89_habits_build_with_a_warning_saying_what_the_board_does(runs):
    # joint 2 at -0.42 rad is -2406.4 hundredths of a degree; (int) truncates towards zero. Natively
    # the host's compiler knows malloc's type and the lab runs; on the board's widths the ring is
    # whatever AL held: the WebAssembly build stops at the first store through it
    native = runs[(LOST_POINTER, "native")]
    assert native.stdout.splitlines()[:2] == ["joint 2 average -2406 (0.01 deg) after 1 calls",
                                              "joint 2 average -2406 (0.01 deg) after 501 calls"]
    wasm = runs[(LOST_POINTER, "wasm")]
    assert wasm.returncode == 3 and wasm.stdout == ""
    assert wasm.stderr.strip().splitlines()[-1] == (
        "crslab sim: implicit_decls_gen_b.c read or wrote outside its memory (a wild pointer or an index far "
        "out of an array) at implicit_decls_gen_b.c:26 in lab() at tick 4100 (t = 4.100 s)")
    for r in (wasm, native):
        warnings = [line for line in r.stderr.splitlines() if line.startswith("crslab sim: warning: ")]
        text = "\n".join(warnings)
        assert "implicit_decls_gen_b.c:24: malloc() is called with no declaration before it" in text, r.stderr
        assert ("the board then reads a 16-bit int from AL, where the C28x returns an int, while malloc() "
                "returns its pointer in XAR4: the pointer is lost: #include <stdlib.h>") in text
        assert "implicit_decls_gen_b.c:29: average() is called with no declaration before it" in text
        assert "implicit_decls_gen_b.c:17: a declaration without a type, which C89 makes an int" in text
        assert "free() is called with no declaration" in text
        # once each: malloc, average, free, the implicit int; with the board's widths the int malloc()
        # is taken to return is stored in a pointer too (the host's compiler knows malloc returns one)
        stored = ("implicit_decls_gen_b.c:24: an integer and a pointer converted into each other without a "
                  "cast")
        assert (stored in text) == (r is wasm)
        assert len(warnings) == (5 if r is wasm else 4), warnings


def test_a_lab_with_every_habit_declared_gets_no_warning(runs):
    assert "warning:" not in runs[("six_params_gen_b.c", "wasm")].stderr
    assert "warning:" not in runs[("six_params_gen_b.c", "native")].stderr


def expected_counts(theta: float) -> int:
    """(long)(theta * 144000 / PI) as the lab computes it: a float product, then a double quotient."""
    return int(float(np.float32(theta) * np.float32(144000)) / 3.1415926535897932384626433832795)


def test_long_arithmetic_prints_the_same_on_both_boards(runs):
    c2, c3 = expected_counts(-0.42), expected_counts(0.24)
    assert (c2, c3) == (-19251, 11000)  # 60480/pi = 19251.1, 34560/pi = 11000.8
    lines = runs[("long_counts_gen_a.c", "wasm")].stdout.splitlines()
    assert lines[:2] == [f"0 us: counts 0 {c2} {c3}, sum {c3}",
                         f"500000 us: counts 0 {c2} {c3}, sum {501 * c3}"]


def test_a_native_run_says_where_the_hosts_widths_and_layout_differ_from_the_boards(runs):
    note = ("crslab sim: note: built natively: int is 32 bits here, 16 on the board, long 64 bits, 32 there, "
            "and its globals lie where the host compiler puts them, not where the TI linker does")
    assert note in runs[("long_counts_gen_a.c", "native")].stderr
    assert "built natively" not in runs[("long_counts_gen_a.c", "wasm")].stderr


def test_the_c28x_check_says_where_an_undeclared_malloc_loses_its_pointer():
    report = check_lab(LABS / "implicit_decls_gen_b.c", sandboxed=False)
    assert not report.skipped, report.skipped
    cuts = [f for f in report.findings if f.flag == "pointer-lost"]
    assert [(f.file, f.line) for f in cuts] == [("implicit_decls_gen_b.c", 24)], report.findings
    assert cuts[0].message.startswith("malloc() has no declaration before this line")


@pytest.mark.parametrize(("text", "said"), [
    ("void lab(void) { }\nstatic void printing(void) { }\n",
     "printing() is static (line 2), so the framework's file cannot call it"),
    ("static void lab(float a) { }\n", "lab() is static (line 1)"),
    ("void lab(float a, float b, float c, float *t1, float *t2, float *t3, int e, int extra) { }\n",
     "lab() takes 8 parameters (line 1); the framework passes 7"),
    ("void lab(void) { }\nvoid printing(int n) { }\n",
     "printing() takes 1 parameters (line 2); the framework calls it with none"),
])
def test_a_definition_the_framework_cannot_call_is_refused_by_its_cause(tmp_path, text, said):
    lab = tmp_path / "odd.c"
    lab.write_text(text)
    with pytest.raises(LabBuildError) as caught:
        build_lab(lab, cache=tmp_path / "cache", sandboxed=False)
    assert str(caught.value) == f"odd.c cannot run on the board: {said}" or said in str(caught.value)
    assert "\n" not in str(caught.value)


def test_defines_no_lab_only_when_there_is_none(tmp_path):
    lab = tmp_path / "no_lab.c"
    lab.write_text("/* lab( in a comment */\nconst char *s = \"void lab(void) {}\";\n#if 0\n"
                   "void lab(void) {}\n#endif\nvoid lab(float a);\nvoid printing(void) { }\n")
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--fast", "--quiet",
                        "--no-c28x-check", "--duration", "0.1"], capture_output=True, text=True, timeout=600)
    assert r.returncode == 2
    assert r.stderr.strip().splitlines()[-1] == "crslab sim: no_lab.c defines no lab() function"


@pytest.mark.parametrize(("text", "parameters", "knr"), [
    ("void lab(float a, float b, float c, float *t1, float *t2, float *t3, int error) { }", 7, False),
    ("void lab(float a, float b, float c, float *t1, float *t2, float *t3)\n{\n}", 6, False),
    ("void lab() { }", 0, False),
    ("void lab(void) { }", 0, False),
    ("void\nlab (a, b, c, t1, t2, t3)\nfloat a, b, c;\nfloat *t1, *t2, *t3;\n{ }", 6, True),
    ("void lab(float (*f)(float, int), int n[3]) { }", 2, False),
])
def test_the_definition_is_read_from_the_text(text, parameters, knr):
    d = lab_definition("void lab(float a);\n" + text)  # a declaration before it is not the definition
    line = 2 + text[:text.index("lab")].count("\n")  # where its name is
    assert d is not None and (d.parameters, d.knr, d.line) == (parameters, knr, line)
    assert printing_definition(text) is None


def test_calls_strings_comments_and_declarations_are_not_definitions():
    text = ('void printing(void);\nvoid f(void) { printing(); lab(1); }\n/* void lab(void) { } */\n'
            'const char *s = "void lab(void) { }";\n')
    assert find_definitions(text, "lab") == []
    assert [d.declared_only for d in find_definitions(text, "printing")] == [True]


def test_grade_s_report_says_the_c89_habits_as_crslab_sim_does(runs, tmp_path):
    """A submission that builds with C89 habits is graded (here it crashes, as its lost pointer makes
    it do), and its report says each habit in one line, as ``crslab sim`` says it on stderr; one
    without habits gets none."""
    subs = tmp_path / "class"
    subs.mkdir()
    for name in ("implicit_decls_gen_b.c", "six_params_gen_b.c"):
        (subs / name).write_bytes((LABS / name).read_bytes())
    out = tmp_path / "grades"
    r = subprocess.run([sys.executable, "-m", "crslab", "grade", str(subs), "--reference",
                        str(LABS / "six_params_gen_b.c"), "--scenario", "hands_off", "--duration", "5.2",
                        "--no-c28x-check", "--jobs", "1", "--out", str(out)],
                       capture_output=True, text=True, timeout=600, env=os.environ)
    assert r.returncode == 1, r.stderr  # implicit_decls_gen_b.c crashes
    # sim names the lab as it was given (its path here); grade by its path in the submission
    sim_said = runs[("implicit_decls_gen_b.c", "wasm")].stderr.splitlines()
    said = [line.removeprefix("crslab sim: ").replace(f"{LABS}{os.sep}", "") for line in sim_said
            if line.startswith("crslab sim: warning: ")]
    assert len(said) == 5 and said[0].startswith("warning: implicit_decls_gen_b.c:")
    report = (out / "reports" / "implicit_decls_gen_b.c.txt").read_text().splitlines()
    assert report[0].startswith("crashed") and report[-5:] == said
    assert not (out / "reports" / "six_params_gen_b.c.txt").exists()  # a pass without habits: no report
    assert "crslab grade: 1 of 2 submissions use C89 habits that newer compilers refuse" in r.stderr
