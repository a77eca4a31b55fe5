"""The run options, each by its own number, through the command a user types: ``--offsets``
(the arm's true resting pose), ``--budget-us`` (lab()'s time budget), ``--rel-tol`` (scaled by
the larger of the two numbers), ``--amax`` (``crslab traj``'s acceleration limit), ``--jobs``
(the worker count grade and sweep use), Gen A's long-line limit (its 2048-byte serial_printf
buffer and transmit ring, framework_facts.h), and transcripts byte-identical at any speed under
seeded encoder noise and faults."""

import json
from pathlib import Path

import numpy as np
import pytest

from crslab import crs
from crslab.cli import main
from crslab.generations import GEN_A
from crslab.regress.transcript import read_golden, write_golden
from crslab.run.api import simulate

LABS = Path(__file__).parent / "labs"
ANGLES = LABS / "motor_angles_rad.c"
# The hand takes the arm to motor zero in 0.2 s and holds it there; the lab prints every 10 ms.
MOTOR_ZERO = """name = "motor_zero"
description = "held at motor zero from 0.2 s"
end = 1.0

[[event]]
at = 0.0
kind = "hand"
motor_deg = [0, 0, 0]
duration = 0.2
"""


class Ran:
    """A command's exit status and what it printed."""

    def __init__(self, returncode, stdout, stderr):
        self.returncode, self.stdout, self.stderr = returncode, stdout, stderr


@pytest.fixture
def crslab(capsys):
    """Run a crslab command in this process (as the console script does, without the start-up)."""
    def run(*args):
        capsys.readouterr()
        status = main([str(a) for a in args])
        out, err = capsys.readouterr()
        return Ran(status, out, err)

    return run


def numbers(line):
    return [float(x) for x in line.split()]


@pytest.fixture(scope="module")
def motor_zero(tmp_path_factory):
    """The motor-zero scenario and a golden file of motor_angles_rad.c on it (the default arm)."""
    folder = tmp_path_factory.mktemp("motor_zero")
    scenario = folder / "motor_zero.toml"
    scenario.write_text(MOTOR_ZERO)
    golden = folder / "golden.txt"
    assert main(["record", "--lab", str(ANGLES), "--scenario", str(scenario), "--no-startup-delay",
                 "-o", str(golden)]) == 0
    return scenario, golden


def test_offsets_move_the_arms_true_resting_pose(crslab, motor_zero, tmp_path):
    scenario, golden = motor_zero
    default = read_golden(golden).body.decode().split("\n\r")
    # the lab's offsets are the default arm's resting pose: at motor zero it reads 0 0 0
    assert numbers(default[0]) == [0, 0.0, -0.4199, 0.2399]  # at rest: the offsets (Gen A truncates)
    np.testing.assert_allclose(numbers(default[95])[1:], [0, 0, 0], atol=2e-4)
    # another arm rests at -0.40, 0.30: each printed angle is true - rest + offset
    transcript = tmp_path / "t.txt"
    r = crslab("sim", "--fast", "--quiet", "--lab", ANGLES, "--scenario", scenario, "--no-startup-delay",
               "--offsets", "-0.40", "0.30", "--transcript", transcript)
    assert r.returncode == 0, r.stderr
    lines = transcript.read_bytes().decode().split("\n\r")
    assert numbers(lines[0]) == numbers(default[0])  # the encoders are zeroed where the arm rests
    assert numbers(lines[95])[0] == 950
    np.testing.assert_allclose(numbers(lines[95])[1:], [0, 0.40 - 0.42, -0.30 + 0.24], atol=2e-4)


def test_rel_tol_scales_by_the_larger_number(crslab, motor_zero, tmp_path):
    """Expected 1050, got 950: off by 100. 0.1 of the larger (105) allows it, 0.1 of the smaller
    (95) would not; 0.09 of the larger (94.5) does not."""
    scenario, golden = motor_zero
    g = read_golden(golden)
    lines = g.body.split(b"\n\r")
    assert lines[95].startswith(b"950 ")
    lines[95] = b"1050 " + lines[95][4:]
    edited = tmp_path / "edited.txt"
    write_golden(edited, g.header, b"\n\r".join(lines))
    r = crslab("check", "--lab", ANGLES, "--golden", edited, "--rel-tol", "0.1")
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.startswith("match: 100 lines within abs tol 0.01, rel tol 0.1")
    r = crslab("check", "--lab", ANGLES, "--golden", edited, "--rel-tol", "0.09")
    assert r.returncode == 1, r.stdout + r.stderr
    assert "line 96 at t = 0.950 s: number 1 is 950, expected 1050 (off by 100)" in r.stdout


def test_budget_counts_the_calls_over_it(crslab, tmp_path):
    """busy_lab.c runs 100 000 rounds of a multiply-add in every lab() call: well over 200 000
    WebAssembly instructions, never near 20 million; a native run is compared in time at 150
    instructions per microsecond (the F28335's 150 MHz)."""
    def run(budget, *extra, lab="busy_lab.c"):
        r = crslab("sim", "--fast", "--quiet", "--lab", LABS / "faulty" / lab, "--scenario",
                   "hands_off", "--no-startup-delay", "--duration", "0.005", "--json",
                   "--budget", budget, *extra)
        assert r.returncode == 0, r.stderr
        return json.loads(r.stderr.strip().splitlines()[-1])

    tight, loose = run(200_000), run(20_000_000)
    assert (tight["budget"], tight["lab_calls"], tight["over_budget"]) == (200_000, 5, 5)
    assert tight["over_budget_ticks"] == [0, 1, 2, 3, 4]
    assert (loose["budget"], loose["lab_calls"], loose["over_budget"]) == (20_000_000, 5, 0)
    # slow_lab.c spins 3 ms of CPU time per call: over 375 000 instructions' 2500 us, never 100 ms
    tight, loose = run(375_000, "--native", lab="slow_lab.c"), run(15_000_000, "--native", lab="slow_lab.c")
    assert (tight["budget"], tight["lab_cost_unit"], tight["over_budget"]) == (2500.0, "us", 5)
    assert (loose["budget"], loose["over_budget"]) == (100000.0, 0)


def test_a_call_costing_exactly_the_budget_is_not_over_it(crslab):
    """The budget's edge: a lab() call over it costs more than the budget, not as much (issue 33).
    Every call of busy_lab.c costs the same count C of instructions: a budget of C counts none of
    its calls over, C - 1 counts every one."""
    def run(budget):
        r = crslab("sim", "--fast", "--quiet", "--lab", LABS / "faulty" / "busy_lab.c", "--scenario",
                   "hands_off", "--no-startup-delay", "--duration", "0.005", "--json", "--budget", budget)
        assert r.returncode == 0, r.stderr
        return json.loads(next(line for line in reversed(r.stderr.splitlines()) if line.startswith("{")))

    loose = run(20_000_000)
    cost = int(loose["lab_cost_max"])
    assert loose["lab_cost_mean"] == cost and loose["lab_calls"] == 5  # every call costs the same
    exact, one_less = run(cost), run(cost - 1)
    assert (exact["budget"], exact["over_budget"]) == (cost, 0)
    assert (one_less["budget"], one_less["over_budget"], one_less["over_budget_ticks"]) == (cost - 1, 5,
                                                                                            [0, 1, 2, 3, 4])


def test_amax_bounds_the_acceleration_and_sets_the_shortest_time(crslab, tmp_path):
    """Li's profile as fast as the acceleration limit allows: T = 2 sqrt(2 L / amax) for the joint
    that moves most (L from the kinematics' own IK), whose peak acceleration is then amax."""
    pts = tmp_path / "pts.csv"
    pts.write_text("x_in,y_in,z_in\n10,0,20\n12,-3,16\n")
    move = np.abs(crs.ik([[12, -3, 16]])[0] - crs.ik([[10, 0, 20]])[0]).max()
    for amax in (2.0, 8.0):
        out = tmp_path / f"traj{amax:g}.csv"
        r = crslab("traj", "crs", "--waypoints", pts, "--vmax", "0", "--amax", amax, "-o", out)
        assert r.returncode == 0, r.stderr
        T = 2 * np.sqrt(2 * move / amax)
        assert f": {T:.3f} s, {int(np.ceil(T * 1000)) + 1} rows at 1000 Hz" in r.stdout
        table = np.loadtxt(out, delimiter=",", skiprows=1)
        assert np.abs(table[:, 7:10]).max() == pytest.approx(amax, rel=1e-4)
        assert np.abs(table[:, 4:7]).max() == pytest.approx(2 * move / T, rel=1e-4)  # Li: 2L/T


class MeetingJob:
    """A job that returns only once ``parties`` jobs are running at the same time (each waits at a
    shared barrier; a lone one gives up after the guard and returns its failure)."""

    def __init__(self, barrier, index):
        self.barrier, self.index = barrier, index

    @property
    def name(self):
        return f"meeting {self.index}"

    def run(self):
        import threading

        try:
            self.barrier.wait(timeout=30)  # a guard only: the partner is already running
        except threading.BrokenBarrierError:
            return "alone"
        return "met"

    def lost(self, status, message):
        return message


def test_jobs_runs_that_many_processes_at_once():
    from crslab.executors.local import LocalExecutor, context

    barrier = context().Barrier(2)
    results = {}
    LocalExecutor(2).run([MeetingJob(barrier, 0), MeetingJob(barrier, 1)],
                         lambda i, result: results.__setitem__(i, result))
    assert results == {0: "met", 1: "met"}


def test_jobs_reaches_grade_and_sweep(crslab, tmp_path):
    """The worker count the command prints is its executor's (grade: tests/test_grade_classes.py
    gives --jobs 3)."""
    r = crslab("sweep", "--lab", LABS / "sweep_pd.c", "--scenario", "hands_off", "--duration", "0.2",
               "--no-startup-delay", "--vary", "friction=0.5:1.5", "--samples", "2", "--jobs", "1",
               "-o", tmp_path / "r.csv")
    assert r.returncode == 0, r.stderr
    assert "1 at a time" in r.stderr
    # one at a time: the samples finish in order
    assert [line.split(":")[0] for line in r.stderr.splitlines() if line.startswith("[")] == [
        "[1/2] sample 0", "[2/2] sample 1"]


def long_line_lab(tmp_path, chars):
    text = (LABS / "long_line_gen_a.c").read_text()
    assert text.count("#define LINE_CHARS 2047") == 1
    lab = tmp_path / f"long_line_{chars}.c"
    lab.write_text(text.replace("#define LINE_CHARS 2047", f"#define LINE_CHARS {chars}"))
    return lab


def test_gen_a_prints_a_line_at_its_2048_byte_limit_and_stops_beyond_it(tmp_path):
    assert GEN_A.printf_buffer_chars == GEN_A.tx_ring_chars == 2048
    at_limit = simulate(long_line_lab(tmp_path, 2047), "hands_off", duration_s=0.25, startup_delay=False)
    dump = bytes(ord("a") + i % 26 for i in range(2045))
    assert at_limit.status == "ok" and at_limit.stats.tx_dropped == 0  # the ring holds all of it too
    assert at_limit.transcript == dump + b"\n\rcall 100\n\rcall 200\n\r"
    beyond = simulate(long_line_lab(tmp_path, 2048), "hands_off", duration_s=0.25, startup_delay=False)
    assert (beyond.status, beyond.exit_status, beyond.transcript) == ("crashed", 3, b"")
    assert beyond.message == (
        "long_line_2048.c: a serial_printf in printing() at tick 0 (t = 0.000 s) formatted 2048 characters; "
        "the board's 2048-byte serial_printf buffer holds 2047 and a terminating NUL, so this line overflows "
        "it and corrupts the board's memory")


NOISE = """name = "noise"
description = "encoder noise on every joint, then on joint 2 alone"
seed = 3
end = 1.0

[[event]]
at = 0.1
kind = "noise"
counts = [30, 60, 20]

[[event]]
at = 0.6
kind = "noise"
counts = 0
joints = [1, 3]
"""
FAULTS = """name = "faults"
description = "random encoder glitches, a stuck encoder, a dead motor"
seed = 9
end = 1.0

[[event]]
at = 0.1
kind = "glitches"
until = 0.9
rate_hz = 100
counts = 3000

[[event]]
at = 0.3
kind = "stuck_encoder"
joint = 3
until = 0.5

[[event]]
at = 0.2
kind = "hand"
motor_deg = [10, 0, 0]
duration = 0.5
"""


@pytest.mark.parametrize("text", [NOISE, FAULTS], ids=["noise", "faults"])
def test_seeded_noise_and_faults_print_byte_identical_at_any_speed(crslab, tmp_path, text):
    scenario = tmp_path / "s.toml"
    scenario.write_text(text)
    fast, paced = tmp_path / "fast.txt", tmp_path / "paced.txt"
    for pace, transcript in ((["--fast"], fast), (["--speed", "7"], paced)):
        r = crslab("sim", *pace, "--quiet", "--lab", ANGLES, "--scenario", scenario, "--no-startup-delay",
                   "--transcript", transcript)
        assert r.returncode == 0, r.stderr
    assert fast.read_bytes() == paced.read_bytes()
    rows = np.array([numbers(line) for line in fast.read_bytes().decode().split("\n\r")[:-1]])
    assert rows.shape == (100, 4)
    readings = rows[10:, 1:]  # from 0.1 s on, where the faults act
    jumps = np.abs(np.diff(readings, axis=0))
    if text is NOISE:
        assert len({tuple(r) for r in rows[10:60, 1:]}) > 30  # the noise shows in every joint
        assert np.ptp(rows[60:, 1]) == 0 and np.ptp(rows[60:, 3]) == 0 and np.ptp(rows[60:, 2]) > 0
    else:
        assert (jumps > 0.03).any()  # glitches of 3000 counts (0.065 rad) were printed
