"""A lab's own encoder offsets read from its text (crslab/contest/offsets.py) are the values the
board holds: each lab below writes them another way (a plain number, a float literal, Gen A's PI
from coecsl.h, the lab's own #define, a cast, an integer division), and its first scope row's
encoder readings (tick 0, the arm at rest: the reading is the offset itself) say what the board
made of them. The values are worked out by hand in the comments."""

import math
import subprocess
import sys

import numpy as np
import pytest

from crslab.contest.offsets import contest_rest, evaluate, lab_offsets
from crslab.lab.includes import with_own_headers
from crslab.plant.model_files import REST_MOTOR_RAD
from crslab.run.api import simulate

GEN_A = '#include <tistdtypes.h>\n#include <coecsl.h>\n#include "user_includes.h"\n#include "math.h"\n'
GEN_B = '#include "math.h"\n#include "F28335Serial.h"\nint UARTprint = 0;\n'
LAB = ("void lab(float t1, float t2, float t3, float *tau1, float *tau2, float *tau3, int error)\n"
       "{\n    *tau1 = 0;\n    *tau2 = 0;\n    *tau3 = 0;\n}\nvoid printing(void) { }\n")

CASES = {
    # name: (the lab's head, offset 2, offset 3 as the board holds them, by hand)
    "plain": (GEN_B + "float offset_Enc2_rad = -0.4;\nfloat offset_Enc3_rad = 0.26;\n", -0.4, 0.26),
    "gen_a_pi": (GEN_A + "float offset_Enc2_rad = -24.0*PI/180.0, offset_Enc3_rad = 15 * PI / 180;\n",
                 -24 * math.pi / 180, 15 * math.pi / 180),
    "defines_and_a_cast": (GEN_B + "#define PI 3.1415926535897932384626433832795\n"
                           "#define OFF3 (0.5f * (float)PI / 4)   /* pi/8 */\n"
                           "float offset_Enc2_rad = -(1.0 / 2.5);\nfloat offset_Enc3_rad = OFF3;\n",
                           -0.4, math.pi / 8),
    "integer_division": (GEN_B + "float offset_Enc2_rad = -1/2 - 0.43;\n"
                         "float offset_Enc3_rad = 0.25f + 1/4;\n", -0.43, 0.25),  # -1/2 and 1/4 are 0 in C
}


@pytest.mark.parametrize("name", list(CASES))
def test_the_offsets_read_from_the_text_are_the_boards(tmp_path, name):
    head, o2, o3 = CASES[name]
    text = head + LAB
    read = lab_offsets(text)
    assert read.rad == pytest.approx((o2, o3), abs=1e-7), read.why
    lab = tmp_path / f"{name}.c"
    lab.write_text(text)
    run = simulate(lab, "hands_off", duration_s=0.002, log=True)
    assert run.status == "ok", run.message
    enc = np.asarray(run.log["enc_rad"][0], float)
    assert enc[1:] == pytest.approx(read.rad, abs=1e-6)


def test_what_cannot_be_read_is_said():
    assert lab_offsets(GEN_B + LAB).why == "it defines no offset_Enc2_rad"
    text = GEN_B + "float offset_Enc2_rad = -0.4;\nfloat offset_Enc3_rad = bench_offset();\n" + LAB
    assert lab_offsets(text).why == "offset_Enc3_rad = bench_offset(): 'bench_offset' is not a constant"
    # a global without an initialiser is zero, as C makes it
    assert lab_offsets(GEN_B + "float offset_Enc2_rad = -0.4;\nfloat offset_Enc3_rad;\n" + LAB).rad == \
        pytest.approx((-0.4, 0.0))


def test_c_s_arithmetic():
    assert evaluate("7 / 2 * 2", {}) == (6.0, "i")
    assert evaluate("-7 / 2", {}) == (-3.0, "i")          # C truncates toward zero
    assert evaluate("0.1f + 0.2f", {}) == (float(np.float32(np.float32(0.1) + np.float32(0.2))), "f")
    assert evaluate("(double)1 / 3", {})[1] == "d"


def test_the_contest_s_rest_is_the_lab_s_own_unless_offsets_are_given():
    text = CASES["plain"][0] + LAB
    own = contest_rest(text)
    assert own.source == "lab" and own.motor_rad == pytest.approx((REST_MOTOR_RAD[0], -0.4, 0.26), abs=1e-7)
    assert "the lab's own offset_Enc2_rad, offset_Enc3_rad" in own.line()
    given = contest_rest(text, (-0.41, 0.25))
    assert given.source == "option" and given.motor_rad == (REST_MOTOR_RAD[0], -0.41, 0.25)
    unread = contest_rest(GEN_B + LAB)
    assert unread.source == "default" and unread.motor_rad == tuple(REST_MOTOR_RAD)
    assert unread.line().endswith("it defines no offset_Enc2_rad")


def test_offsets_kept_in_the_lab_s_own_headers_are_its_own(tmp_path):
    """A team that keeps its globals in a header of its own (its bench's offsets among them, one
    through a header that header includes) rests where they say: the board's first readings are
    them, and so is the contest's rest, for ``crslab contest`` as for ``grade --contest``."""
    (tmp_path / "bench.h").write_text('#define OFF2 (-0.41f)\nfloat offset_Enc2_rad = OFF2;\n'
                                      '#include "rest.h"\n')
    # a header's tentative definition of offset 3 (no value): the lab's, with its value, is the one
    (tmp_path / "rest.h").write_text("float offset_Enc3_rad;\n")
    text = GEN_B + '#include "bench.h"\nfloat offset_Enc3_rad = 0.25;\n' + LAB
    lab = tmp_path / "final.c"
    lab.write_text(text)
    assert lab_offsets(text).why == "it defines no offset_Enc2_rad"      # the lab's text alone
    rest = contest_rest(with_own_headers(lab, text))
    assert rest.source == "lab"
    assert rest.motor_rad[1:] == pytest.approx((-0.41, 0.25), abs=1e-7)
    run = simulate(lab, "hands_off", duration_s=0.002, log=True)
    assert run.status == "ok", run.message
    assert np.asarray(run.log["enc_rad"][0], float)[1:] == pytest.approx(rest.motor_rad[1:], abs=1e-6)
    r = subprocess.run([sys.executable, "-m", "crslab", "contest", "--lab", str(lab), "--duration", "4.2"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 1, r.stderr                      # four tasks not done by a lab that does nothing
    assert "rest      -0.4100 0.2500 rad: the lab's own offset_Enc2_rad, offset_Enc3_rad" in r.stdout


def test_a_lab_s_own_headers_are_read_up_to_what_a_build_s_copy_holds(tmp_path, monkeypatch):
    """A folder of huge headers is not read whole into crslab's own process: each up to
    MAX_BYTES, all up to MAX_TOTAL_BYTES (here made 40 bytes), the rest read as empty."""
    from crslab.lab import includes

    monkeypatch.setattr(includes, "MAX_TOTAL_BYTES", 40)
    (tmp_path / "a.h").write_text("float offset_Enc2_rad = -0.41;\n")       # 31 bytes
    (tmp_path / "b.h").write_text("float offset_Enc3_rad = 0.25;\n")        # 9 of its 30 fit
    (tmp_path / "c.h").write_text("int c;\n")                              # none fits
    lab = tmp_path / "final.c"
    lab.write_text('#include "a.h"\n#include "b.h"\n#include "c.h"\n')
    assert includes.header_texts(lab) == [("a.h", "float offset_Enc2_rad = -0.41;\n"), ("b.h", "float off"),
                                          ("c.h", "")]
    assert lab_offsets(with_own_headers(lab, lab.read_text())).why == "it defines no offset_Enc3_rad"
