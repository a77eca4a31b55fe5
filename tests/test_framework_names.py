"""Every name a lab can use through the real framework's headers is there in crslab's stand-ins
(csrc/firmware/include), in both generations: tests/data/framework_names.toml lists them, read from
the real headers. A translation unit per generation includes what that generation's lab files
include and uses every name (a macro defined, a type declared, a variable's and a function's
address taken); it must compile. And a course lab that relies on the real include closure (bool
without <stdbool.h> in Gen B) compiles and runs."""

import subprocess
import tomllib
from pathlib import Path

import pytest

from crslab.lab.build import SHIM_INCLUDE
from crslab.lab.compiler import find_compiler
from crslab.run.api import simulate

NAMES = Path(__file__).parent / "data" / "framework_names.toml"
LAB_INCLUDES = {"A": "#include <tistdtypes.h>\n#include <coecsl.h>\n#include \"user_includes.h\"\n",
                "B": "#include \"math.h\"\n#include \"F28335Serial.h\"\n"}


def names(generation: str) -> dict[str, list[str]]:
    out: dict[str, list[str]] = {"macros": [], "types": [], "variables": [], "functions": []}
    for header in tomllib.loads(NAMES.read_text())["header"]:
        assert header["source"], header["header"]
        if generation in header["generations"]:
            for kind in out:
                out[kind] += header.get(kind, [])
    return out


def uses_of_every_name(generation: str) -> str:
    n = names(generation)
    lines = [LAB_INCLUDES[generation]]
    for macro in n["macros"]:
        lines.append(f"#ifndef {macro}\n#error {macro} is not defined\n#endif")
    for i, t in enumerate(n["types"]):
        lines.append(f"{t} *crs_type_{i};")
    lines.append("void crs_uses(void) {")
    lines += [f"    (void)&{v};" for v in n["variables"]]
    lines += [f"    (void){f};" for f in n["functions"]]
    lines.append("}")
    return "\n".join(lines) + "\n"


def compile_c(text: str, tmp_path: Path) -> subprocess.CompletedProcess:
    source = tmp_path / "uses.c"
    source.write_text(text)
    cc = find_compiler()
    return subprocess.run([*cc.argv, "-std=c11", "-fsyntax-only", "-Werror=implicit-function-declaration",
                           "-I", str(SHIM_INCLUDE), str(source)], capture_output=True, text=True)


@pytest.mark.parametrize("generation", ["A", "B"])
def test_every_name_of_the_real_headers_is_in_crslab_s_stand_ins(tmp_path, generation):
    n = names(generation)
    assert sum(map(len, n.values())) > (150 if generation == "A" else 200)
    r = compile_c(uses_of_every_name(generation), tmp_path)
    assert r.returncode == 0, r.stderr[-4000:]


def test_the_check_fails_for_a_name_the_stand_ins_lack(tmp_path):
    """The translation unit is a real check: a name no header has makes it fail, naming it."""
    text = uses_of_every_name("B").replace("    (void)&SerialA;", "    (void)&SerialZ;")
    r = compile_c(text, tmp_path)
    assert r.returncode != 0 and "SerialZ" in r.stderr
    text = uses_of_every_name("B").replace("#ifndef BIT15\n#error BIT15", "#ifndef BIT16\n#error BIT16")
    r = compile_c(text, tmp_path)
    assert r.returncode != 0 and "BIT16 is not defined" in r.stderr


def test_gen_a_does_not_get_gen_b_s_standard_headers(tmp_path):
    """Gen A's older DSP2833x_Device.h includes no <stdbool.h>: a Gen A file may define its own bool."""
    text = LAB_INCLUDES["A"] + "typedef int bool;\nbool ready = 1;\n"
    r = compile_c(text, tmp_path)
    assert r.returncode == 0, r.stderr
    r = compile_c(LAB_INCLUDES["B"] + "typedef int bool;\n", tmp_path)
    assert r.returncode != 0  # in Gen B bool is <stdbool.h>'s, as on the board


GEN_B_BOOL_LAB = """/* A Gen B lab in the course's style that uses bool, true and false without including
 * <stdbool.h> (the framework's headers bring it), and size_t and uint16_t likewise. */
#include "math.h"
#include "F28335Serial.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
int UARTprint = 0;
long mycount = 0;
bool moving = false;
size_t prints = 0;
uint16_t led_bits = BIT2 | BIT0;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    moving = (mycount % 1000) < 500 ? true : false;
    if ((mycount % 500) == 0) {
        prints++;
        UARTprint = 1;
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%d %d %d\\n\\r", moving ? 1 : 0, (int)prints, (int)led_bits);
}
"""


def test_a_gen_b_lab_using_bool_without_stdbool_compiles_and_runs(tmp_path):
    lab = tmp_path / "lab_bool.c"
    lab.write_text(GEN_B_BOOL_LAB)
    run = simulate(lab, "hands_off", duration_s=5.2)
    assert run.status == "ok", run.message
    assert run.lines() == ["1 1 5", "0 2 5", "1 3 5"]  # prints at 4.1, 4.6, 5.1 s
