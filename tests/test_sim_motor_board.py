"""The motor board between the framework and the arm (docs/framework.md section 5): on Gen B's Piccolo
board a joint commanded beyond 4 units for 500 consecutive ms cuts every output until its command
is back within 4 units. Reported on stderr as it happens, as a scope signal, in the summary and in
the run's result; ``--motor-board`` chooses the board, by default the lab's generation's."""

import csv
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from crslab.run.api import simulate

LABS = Path(__file__).parent / "labs"
SATURATING = LABS / "saturating_gen_b.c"  # +-4.5 for 2 s from 4.1 s, then 0 for 0.5 s, then 1


@pytest.fixture(scope="module")
def saturated():
    return simulate(SATURATING, "hands_off", duration_s=6.7, log=True)


def test_a_saturated_gen_b_controller_goes_limp_after_500_ms_and_comes_back_when_it_commands_0(saturated):
    log = saturated.log
    tick = log["tick"][:, 0]
    applied = log["tau_applied"][:, 0]
    off = log["motor_board_off"][:, 0]
    first_500_ms = (tick >= 4100) & (tick < 4600)
    np.testing.assert_array_equal(np.abs(applied[first_500_ms]), 4.5)  # 1350 PWM counts: > 1200
    cut = (tick >= 4600) & (tick < 6100)
    assert np.all(applied[cut] == 0.0) and np.all(off[cut] == 1)
    # at 6.1 s the lab commands 0 (within 4 units): the board is back; from 6.6 s its 1 unit arrives
    assert np.all(off[tick >= 6100] == 0)
    np.testing.assert_array_equal(applied[tick >= 6600], 1.0)
    assert saturated.stats.motor_board_events == ((4600, 1, True), (6100, 1, False))
    assert saturated.stats.motor_board_cutouts == 1


def test_without_a_motor_board_the_saturated_commands_reach_the_arm():
    run = simulate(SATURATING, "hands_off", duration_s=6.1, log=True, motor_board="none")
    applied = run.log["tau_applied"][4100:6100, 0]
    np.testing.assert_array_equal(np.abs(applied), 4.5)
    assert run.stats.motor_board_events == () and run.stats.motor_board == "none"


def test_gen_a_labs_default_to_no_motor_board_and_gen_b_to_the_piccolo():
    gen_a = simulate(LABS / "persistent_tau.c", "hands_off", duration_s=5.5, log=True)
    assert gen_a.stats.motor_board == "none"
    # tau1 = 40, clamped to 5 and applied as long as the arm is inside the envelope
    inside = gen_a.log["safety"][4100:4700, 0] == 0
    assert inside.sum() > 100
    np.testing.assert_array_equal(gen_a.log["tau_applied"][4100:4700, 0][inside], 5.0)
    piccolo = simulate(LABS / "persistent_tau.c", "hands_off", duration_s=5.5, log=True,
                       motor_board="piccolo")
    assert piccolo.stats.motor_board == "piccolo"
    # the Piccolo board takes whole PWM counts, 300 per unit (the DSP truncates): tau2 = 0.5 is
    # 150 counts, the hold controller's outputs are whole counts too
    counts = piccolo.log["tau_applied"][4100:] * 300
    np.testing.assert_allclose(counts, np.round(counts), atol=1e-9)
    assert np.any(np.abs(gen_a.log["tau_applied"][4100:] * 300 % 1) > 1e-6)  # no board: not


def test_crslab_sim_reports_cutouts_on_stderr_in_the_summary_and_the_csv(tmp_path):
    out = tmp_path / "scopes.csv"
    cmd = [sys.executable, "-m", "crslab", "sim", "--fast", "--lab", str(SATURATING), "--scenario",
           "hands_off", "--duration", "6.7", "--csv", str(out), "--no-stdin"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    lines = r.stderr.splitlines()
    assert ("crslab sim: motor board: every output cut at tick 4600 (t = 4.600 s): joint 1 commanded beyond "
            "4 units for 500 ms") in lines
    assert "crslab sim: motor board: outputs back at tick 6100 (t = 6.100 s)" in lines
    assert lines[-1].endswith("; motor board: 1 cut-out")
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    column = rows[0].index("motor_board_off [0/1]")
    off_ticks = [int(row[0]) for row in rows[1:] if row[column] == "1"]
    assert off_ticks == list(range(4600, 6100))
    r = subprocess.run([*cmd[:-3], "--json", "--motor-board", "none"], capture_output=True, text=True,
                       timeout=120)
    info = json.loads(r.stderr.splitlines()[-1])
    assert info["motor_board"] == "none" and info["motor_board_cutouts"] == 0
    assert "motor board" not in r.stderr


def test_a_golden_file_records_the_motor_board_and_check_uses_it(tmp_path):
    golden = tmp_path / "g.txt"
    crslab = [sys.executable, "-m", "crslab"]
    common = ["--lab", str(SATURATING), "--scenario", "hands_off", "--duration", "4.2"]
    r = subprocess.run([*crslab, "record", *common, "--motor-board", "none", "-o", str(golden)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "# motor_board: none\n" in golden.read_text()
    r = subprocess.run([*crslab, "check", "--lab", str(SATURATING), "--golden", str(golden)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    golden.write_text(golden.read_text().replace("# motor_board: none", "# motor_board: turbo"))
    r = subprocess.run([*crslab, "check", "--lab", str(SATURATING), "--golden", str(golden)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    line = golden.read_text().splitlines().index("# motor_board: turbo") + 1
    assert r.stderr.strip() == (f"crslab check: {golden}:{line}: motor_board: must be one of none, piccolo, "
                                "got 'turbo'")


def test_cutout_lines_come_in_tick_order_with_the_scenarios_announcements(tmp_path):
    scenario = tmp_path / "off.toml"
    scenario.write_text('name = "off"\nend = 6.7\n\n'
                        '[[event]]\nat = 4.5\nkind = "expect"\nmotor_board_off = false\n\n'
                        '[[event]]\nat = 5.0\nkind = "expect"\nmotor_board_off = true\n')
    for quiet in ([], ["--quiet"]):
        r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--lab", str(SATURATING),
                            "--scenario", str(scenario), "--no-stdin", *quiet],
                           capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, r.stderr
        said = [line for line in r.stderr.splitlines()
                if line.startswith(("crslab sim: t = ", "crslab sim: motor board:"))]
        expected = ["crslab sim: t = 4.5 s: expect the motor board on: met",
                    "crslab sim: motor board: every output cut at tick 4600 (t = 4.600 s): joint 1 commanded "
                    "beyond 4 units for 500 ms",
                    "crslab sim: t = 5.0 s: expect the motor board off: met",
                    "crslab sim: motor board: outputs back at tick 6100 (t = 6.100 s)"]
        # --quiet: no announcements, the motor board's lines still
        assert said[:4] == (expected if not quiet else expected[1::2])
