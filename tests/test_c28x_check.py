"""What the board's arithmetic would have said: a lab compiled a second time with the C28x's widths
(int 16 bits, long 32, double 32) is reported where its result differs from the host's, with
file and line; on a lab's first ``crslab sim``, in ``crslab grade``'s reports, off with
``--no-c28x-check``. The expected lines are found in the test lab by their ``C28X`` marks, the
values by 16-bit arithmetic done here."""

import subprocess
import sys
from pathlib import Path

import pytest

from crslab.lab.c28x_check import check_lab

LABS = Path(__file__).parent / "labs"
OVERFLOW = LABS / "c28x_overflow_gen_b.c"
CLEAN = [LABS / "lab1_own_ik.c", LABS / "pd_steps.c", LABS / "sweep_pd.c"]


def int16(value: int) -> int:
    """``value`` wrapped to a 16-bit two's complement int, as the C28x stores it."""
    return (value + 2**15) % 2**16 - 2**15


def marked_lines(path: Path) -> list[int]:
    return [i + 1 for i, line in enumerate(path.read_text().splitlines()) if "C28X:" in line]


def crslab(*args, cwd=None, env=None):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=300, cwd=cwd, env=env)


def test_a_lab_that_overflows_16_bits_is_reported_line_by_line():
    report = check_lab(OVERFLOW)
    assert not report.skipped
    assert [f.line for f in report.findings] == marked_lines(OVERFLOW)  # and nowhere else (not area_ok)
    by_line = {f.line: f.message for f in report.findings}
    product, minute, counts, bound = marked_lines(OVERFLOW)
    assert f"result is {int16(300 * 300)} with type 'int'" in by_line[product]  # 24464
    assert f"changes value from 60000 to {int16(60000)}" in by_line[minute]  # -5536
    assert "changes value from 16777217 to 16777216" in by_line[counts]  # 2**24 + 1: 24 bits of mantissa
    assert "comparison of constant 40000" in by_line[bound] and "always false" in by_line[bound]
    lines = report.lines()
    assert lines[0].startswith("warning: 4 places where the C28x's widths change a result")
    assert lines[1] == f"  c28x_overflow_gen_b.c:{product}: {by_line[product]}"
    native = report.lines(native=True)  # a native build computes with the host's widths
    assert native[0].startswith("warning: 4 places where the board's arithmetic gives another result than "
                                "this native build") and native[1:] == lines[1:]


@pytest.mark.parametrize("lab", CLEAN, ids=lambda p: p.name)
def test_labs_whose_arithmetic_fits_the_board_get_nothing(lab):
    report = check_lab(lab)
    assert report.findings == () and not report.skipped and report.lines() == []


def test_the_first_sim_of_a_lab_says_it_later_ones_do_not_and_the_option_turns_it_off(tmp_path):
    env = {**__import__("os").environ, "CRSLAB_CACHE_DIR": str(tmp_path / "cache")}
    lab = tmp_path / "lab.c"
    lab.write_text(OVERFLOW.read_text())
    run = ["sim", "--lab", lab, "--fast", "--quiet", "--no-stdin", "--duration", "4.2"]
    r = crslab(*run, "--no-c28x-check", env=env)
    assert r.returncode == 0 and "C28x's widths change" not in r.stderr
    r = crslab(*run, env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines() == ["24464 90000"]  # crslab prints what the host computes ...
    said = [line for line in r.stderr.splitlines() if line.startswith("crslab sim:   lab.c:")]
    assert [int(line.split(":")[2]) for line in said] == marked_lines(OVERFLOW)  # ... and the board differs
    assert "crslab sim: warning: 4 places where the C28x's widths change a result" in r.stderr
    r = crslab(*run, env=env)
    assert r.returncode == 0 and "C28x's widths change" not in r.stderr  # said once per lab content
    lab.write_text(OVERFLOW.read_text() + "\n/* changed */\n")
    assert "C28x's widths change" in crslab(*run, env=env).stderr  # a changed file is checked again


def test_grade_reports_say_it_for_each_submission(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    (subs / "alice.c").write_text((LABS / "lab1_own_ik.c").read_text())
    (subs / "bob.c").write_text(OVERFLOW.read_text())
    r = crslab("grade", subs, "--reference", LABS / "lab1_own_ik.c", "--duration", "4.2", "--jobs", "1",
               "-o", tmp_path / "out")
    assert r.returncode == 1, r.stderr  # bob's transcript differs
    assert "1 of 2 submissions have places where the C28x's widths change a result" in r.stderr
    report = (tmp_path / "out" / "reports" / "bob.c.txt").read_text()
    assert f"bob.c:{marked_lines(OVERFLOW)[0]}: overflow in expression; result is 24464" in report
    assert not (tmp_path / "out" / "reports" / "alice.c.txt").exists()  # passed, nothing to say
    r = crslab("grade", subs, "--reference", LABS / "lab1_own_ik.c", "--duration", "4.2", "--jobs", "1",
               "-o", tmp_path / "quiet", "--no-c28x-check")
    assert "C28x's widths change" not in (tmp_path / "quiet" / "reports" / "bob.c.txt").read_text()
