"""Every scenario event kind shows its effect in what the lab prints or in the plant's state."""

from pathlib import Path

import numpy as np
import pytest

from crslab import crs
from crslab.run.api import simulate
from crslab.scenario.load import ScenarioError

LABS = Path(__file__).parent / "labs"
RAD_PER_COUNT = np.pi / 144000


def write(tmp_path_factory, text, name="s.toml"):
    path = tmp_path_factory.mktemp("scenario") / name
    path.write_text(text)
    return path


def at(run, t_s):
    """Index of the scope row of tick t_s * 1000."""
    return int(np.searchsorted(run.log["tick"][:, 0], round(t_s * 1000)))


def printed(run, t_s):
    """The numbers of the first line of the last print at or before t_s."""
    last = max(tick for tick, _ in run.calls if tick <= t_s * 1000)
    line = next(d for tick, d in run.calls if tick == last).decode()
    return [float(v) for v in line.split()]


# -- writes: watched variables and Simulink inputs -----------------------------------------------

@pytest.fixture(scope="module")
def writes(tmp_path_factory):
    path = write(tmp_path_factory, """
end = 5.05
[[event]]
at = 4.45
kind = "set"
var = "gain"
value = 2.25
[[event]]
at = 4.55
kind = "set"
var = "table"
index = 2
value = -7
[[event]]
at = 4.65
kind = "set"
var = "mode"
value = 3.6
[[event]]
at = 4.75
kind = "simulink"
values = [100, -200]
[[event]]
at = 4.85
kind = "simulink"
input = 7
value = -32768
[[event]]
at = 4.95
kind = "simulink"
input = 1
value = 5
""")
    return simulate(LABS / "watch_inputs.c", str(path))


def test_set_writes_scalars_and_array_elements_between_ticks(writes):
    lines = writes.lines()
    assert lines[0] == "gain 1.50 mode 0 table2 0.00 simu 0 0 0"          # 4.1 s: initial values
    assert lines[4] == "gain 2.25 mode 0 table2 0.00 simu 0 0 0"          # 4.5 s
    assert lines[5] == "gain 2.25 mode 0 table2 -7.00 simu 0 0 0"         # 4.6 s: table[2]
    assert lines[6] == "gain 2.25 mode 4 table2 -7.00 simu 0 0 0"         # 4.7 s: int rounded


def test_simulink_inputs_reach_the_lab_and_others_keep_their_value(writes):
    lines = writes.lines()
    assert lines[7] == "gain 2.25 mode 4 table2 -7.00 simu 100 -200 0"
    assert lines[8] == "gain 2.25 mode 4 table2 -7.00 simu 100 -200 -32768"
    assert lines[9] == "gain 2.25 mode 4 table2 -7.00 simu 5 -200 -32768"


def test_an_event_applies_before_its_own_tick(tmp_path_factory):
    path = write(tmp_path_factory, 'end = 4.2\n[[event]]\nat = 4.1\nkind = "set"\nvar = "gain"\nvalue = 9\n')
    run = simulate(LABS / "watch_inputs.c", str(path))
    assert run.calls[0] == (4100, b"gain 9.00 mode 0 table2 0.00 simu 0 0 0\n\r")


def test_a_write_to_an_unwatched_variable_stops_before_running(tmp_path_factory):
    path = write(tmp_path_factory, 'end = 6\n[[event]]\nat = 5\nkind = "set"\nvar = "torquejoint"\nvalue = 1')
    with pytest.raises(ScenarioError, match=r"s.toml:5: var: torquejoint is not a watched .* of lab1_kinem"):
        simulate(None, str(path))


# -- the hand: targets, hold, release ------------------------------------------------------------

@pytest.fixture(scope="module")
def hand(tmp_path_factory):
    path = write(tmp_path_factory, """
end = 10.0
[[event]]
at = 4.2
kind = "hand"
xyz_in = [12, 3, 15]
duration = 1.0
[[event]]
at = 6.5
kind = "hand"
dh_deg = [0, 0, 0]
duration = 1.0
hold = 1.0
""")
    return simulate(None, str(path), log=True)


def test_hand_moves_to_an_xyz_target_through_ik(hand):
    # the default lab prints motor angles, FK xyz and IK angles every 0.5 s
    xyz = [float(v) for v in hand.lines()[3 * 4 + 1].split()]  # the print at 6.1 s
    np.testing.assert_allclose(xyz, [12, 3, 15], atol=0.05)


def test_the_hand_follows_a_minimum_jerk_path(hand):
    # the move at 6.5 s to DH zero over 1 s: q = start + (target - start)(10 s^3 - 15 s^4 + 6 s^5)
    t, q = hand.log["tick"][:, 0], hand.log["qpos_dh_rad"]
    rows = (t >= 6500) & (t <= 7600)
    s = np.clip((t[rows] - 6500) / 1000.0, 0.0, 1.0)[:, None]
    start = q[at(hand, 6.5)]
    minimum_jerk = start - start * s**3 * (10 - 15 * s + 6 * s**2)
    cubic = start - start * s**2 * (3 - 2 * s)
    assert np.abs(start).max() > 0.5  # a real move
    assert np.abs(q[rows] - minimum_jerk).max() < 0.01 < 0.05 < np.abs(q[rows] - cubic).max()


def test_hold_then_release_lets_the_hold_controller_take_the_arm_back(hand):
    q = hand.log["qpos_dh_rad"]
    np.testing.assert_allclose(q[at(hand, 8.4)], [0, 0, 0], atol=0.01)  # held at DH zero
    assert hand.log["safety"][at(hand, 8.4), 0] == 1                      # outside the envelope
    # released at 8.5 s: gravity alone would let the stretched arm fall (th2 DH +0.35 rad within
    # 0.5 s, with every motor dead). The framework's hold controller instead pulls it back toward
    # its references, which trail the hand's path from inside the envelope by at most 0.15 rad
    # (re-anchoring): th2 rises and th3 moves toward its 0.15 rad bound, and the arm stays there
    moved = q[at(hand, 9.9)] - q[at(hand, 8.4)]
    assert moved[1] < -0.03 and 0.05 < moved[2] < 0.15
    assert np.abs(moved).max() < 0.15
    assert np.abs(q[at(hand, 9.9)] - q[at(hand, 9.0)]).max() < 1e-3  # held, not falling
    applied = hand.log["tau_applied"][at(hand, 9.0):at(hand, 9.9)]
    assert np.all(hand.log["safety"][at(hand, 9.0):at(hand, 9.9), 0] == 1)
    assert np.abs(applied[:, 1]).min() > 0.5  # joint 2 held up against gravity by the hold's output


# -- plant: resting pose, friction, end mass -----------------------------------------------------

def test_true_resting_pose_from_the_scenario(tmp_path_factory):
    path = write(tmp_path_factory, """
end = 6.2
[plant]
rest_motor_rad = [0, -0.30, 0.10]
[[event]]
at = 4.2
kind = "hand"
motor_deg = [0, 0, 0]
duration = 1.0
""")
    run = simulate(None, str(path), log=True)
    np.testing.assert_allclose(crs.dh_to_motor(run.log["qpos_dh_rad"][0]), [0, -0.30, 0.10], atol=1e-9)
    # the lab assumes the arm rested at its offsets (-0.42, 0.24): at rest it prints them ...
    assert printed(run, 4.1) == pytest.approx(np.degrees([0, -0.42, 0.24]), abs=0.01)
    # ... and at motor zero it prints the error of its offsets
    assert printed(run, 6.1) == pytest.approx(np.degrees([0, -0.12, 0.14]), abs=0.02)


@pytest.fixture(scope="module")
def plant_runs(tmp_path_factory):
    def run(text):
        return simulate(None, str(write(tmp_path_factory, text)), log=True)

    return {
        "none": run("end = 6.5\n"),
        "friction_off": run('end = 6.5\n[[event]]\nat = 5.0\nkind = "friction"\nscale = 0.0\n'),
        "mass": run('end = 6.5\n[[event]]\nat = 5.0\nkind = "end_mass"\nkg = "course"\n'),
        "mass_and_friction": run('end = 6.5\n[plant]\nend_mass_kg = "course"\nfriction_scale = 4.0\n'),
        "mass_from_start": run('end = 6.5\n[plant]\nend_mass_kg = "course"\n'),
    }


def test_friction_holds_the_resting_arm_and_removing_it_lets_the_arm_move(plant_runs):
    still, free = plant_runs["none"], plant_runs["friction_off"]
    q0 = still.log["qpos_dh_rad"][0]
    assert np.abs(still.log["qpos_dh_rad"] - q0).max() < 1e-3
    q = free.log["qpos_dh_rad"]
    assert np.abs(q[at(free, 4.99)] - q0).max() < 1e-3  # nothing before the event
    assert np.abs(q[at(free, 6.0)] - q0).max() > 0.02   # it sags once friction is gone
    assert still.lines() != free.lines() and still.lines()[:6] == free.lines()[:6]


def test_end_mass_makes_the_forearm_sag_unless_friction_is_scaled_up(plant_runs):
    q0 = plant_runs["none"].log["qpos_dh_rad"][0]
    mass = plant_runs["mass"]
    assert np.abs(mass.log["qpos_dh_rad"][at(mass, 4.99)] - q0).max() < 1e-3
    sag_deg = printed(mass, 6.1)[2] - printed(mass, 4.6)[2]  # motor 3: the forearm's angle
    assert sag_deg > 2.0
    assert printed(plant_runs["mass_from_start"], 4.1)[2] > 14.5       # sagged before lab() starts
    assert printed(plant_runs["mass_and_friction"], 6.1)[2] == pytest.approx(13.75, abs=0.05)


# -- faults --------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def encoder_faults(tmp_path_factory):
    path = write(tmp_path_factory, """
end = 8.0
[[event]]
at = 4.2
kind = "noise"
counts = 50
joint = 2
until = 5.0
[[event]]
at = 4.2
kind = "noise"
counts = 20
joint = 1
until = 5.1
[[event]]
at = 5.2
kind = "glitch"
joint = 1
counts = 5000
[[event]]
at = 5.5
kind = "stuck_encoder"
joint = 3
until = 7.5
[[event]]
at = 5.5
kind = "noise"
joint = 3
counts = 30
until = 7.5
[[event]]
at = 5.5
kind = "hand"
motor_deg = [0, 0, 0]
duration = 1.5
""")
    return simulate(None, str(path), log=True)


def test_noise_on_chosen_joints_for_a_while(encoder_faults):
    run = encoder_faults
    t, enc = run.log["tick"][:, 0], run.log["enc_rad"]
    both, first_only, none = (t >= 4200) & (t < 5000), (t >= 5000) & (t < 5100), (t >= 5100) & (t < 5200)
    assert enc[both, 1].std() / RAD_PER_COUNT == pytest.approx(50, rel=0.2)
    assert enc[both, 0].std() / RAD_PER_COUNT == pytest.approx(20, rel=0.2)
    assert enc[both, 2].std() == 0
    # joint 2's noise ends at 5.0 s; joint 1's goes on until 5.1 s
    assert enc[first_only, 1].std() == 0 and enc[first_only, 0].std() / RAD_PER_COUNT > 10
    assert enc[none].std(axis=0).max() == 0


def test_a_glitch_lasts_exactly_one_tick(encoder_faults):
    run = encoder_faults
    i = at(run, 5.2)
    counts = (run.log["enc_rad"][i - 1:i + 2, 0] - run.log["enc_rad"][i - 1, 0]) / RAD_PER_COUNT
    np.testing.assert_allclose(counts, [0, 5000, 0], atol=0.01)


def test_a_stuck_encoder_keeps_its_reading_while_the_joint_moves(encoder_faults):
    run = encoder_faults
    t, enc = run.log["tick"][:, 0], run.log["enc_rad"]
    motor = crs.dh_to_motor(run.log["qpos_dh_rad"])
    stuck = (t >= 5500) & (t < 7500)
    assert np.ptp(enc[stuck, 2]) == 0 and np.ptp(motor[stuck, 2]) > 0.2  # noisy, yet frozen
    assert enc[at(run, 7.6), 2] == pytest.approx(motor[at(run, 7.6), 2], abs=2 * RAD_PER_COUNT)
    # the transcript shows it: the forearm's printed angle stays at rest while the arm reaches motor zero
    assert printed(run, 7.1) == pytest.approx([0, 0, 13.75], abs=0.05)
    assert printed(run, 7.6) == pytest.approx([0, 0, 0], abs=0.05)


@pytest.fixture(scope="module")
def motor_faults(tmp_path_factory):
    path = write(tmp_path_factory, """
end = 6.5
[[event]]
at = 0
kind = "dead_motor"
joint = 1
until = 5.0
[[event]]
at = 5.5
kind = "estop"
wrist_rad = 0.05
[[event]]
at = 6.0
kind = "estop"
""")
    return simulate(LABS / "open_loop_tau1.c", str(path), log=True)


def test_a_dead_motor_outputs_nothing_until_it_comes_back(motor_faults):
    run = motor_faults
    t, applied, q = run.log["tick"][:, 0], run.log["tau_applied"], run.log["qpos_dh_rad"]
    dead = (t >= 4100) & (t < 5000)
    assert np.all(run.log["tau_lab"][dead, 0] == 1.0) and np.all(applied[dead, 0] == 0.0)
    assert abs(q[at(run, 4.99), 0]) < 1e-6
    assert applied[at(run, 5.0), 0] == 1.0 and q[at(run, 5.4), 0] > 0.3


def test_the_wrist_estop_latches_every_output_to_zero_only_past_0_11_rad(motor_faults):
    run = motor_faults
    t, applied = run.log["tick"][:, 0], run.log["tau_applied"]
    assert np.any(applied[(t >= 5500) & (t < 6000)] != 0)     # 0.05 rad: nothing happens
    assert np.all(applied[t >= 6000] == 0) and run.stats.estop_latched == 1
    assert run.log["tau_lab"][-1, 0] == 1.0                    # lab() still runs


def test_the_end_time_ends_the_run(motor_faults, writes):
    assert motor_faults.end_tick == 6500 and motor_faults.log["tick"][-1, 0] == 6499
    assert writes.end_tick == 5050 and writes.calls[-1][0] == 5000


# -- seeded faults -------------------------------------------------------------------------------

def seeded(tmp_path_factory, seed):
    path = write(tmp_path_factory, f"""
end = 7.0
seed = {seed}
[[event]]
at = 4.0
kind = "noise"
counts = 300
[[event]]
at = 4.0
kind = "glitches"
until = 7.0
rate_hz = 4
counts = 20000
""")
    return simulate(None, str(path), log=True)


def test_seeded_faults_repeat_with_the_same_seed_and_differ_with_another(tmp_path_factory):
    a, b, c = seeded(tmp_path_factory, 11), seeded(tmp_path_factory, 11), seeded(tmp_path_factory, 12)
    assert a.transcript == b.transcript and np.array_equal(a.log["enc_rad"], b.log["enc_rad"])
    assert a.transcript != c.transcript
    jumps = np.abs(np.diff(a.log["enc_rad"], axis=0)) > 5000 * RAD_PER_COUNT
    assert jumps.any(axis=1).sum() >= 2  # the glitches are there


def test_every_event_class_has_its_effect_on_the_simulator_side():
    from crslab.scenario.kinds import EVENT_KINDS
    from crslab.worker.event_effects import EFFECTS

    assert set(EVENT_KINDS.values()) <= set(EFFECTS)


def test_watched_variables_in_the_lab_s_own_header_are_written_and_listed(tmp_path_factory):
    """A team that keeps its watched variables in a header of its own (``#pragma DATA_SECTION``
    there too) has them watched as the board's MATLAB tools see them: a scenario writes them,
    ``crslab vars`` lists them at their header's line, the map places them in their sections."""
    import json
    import subprocess
    import sys

    folder = tmp_path_factory.mktemp("own_header")
    text = (LABS / "watch_inputs.c").read_text()
    watched = text[text.index("#pragma DATA_SECTION(gain"):text.index("long mycount")]
    (folder / "globals.h").write_text("/* the lab's watched variables */\n" + watched)
    (folder / "watch_inputs.c").write_text(text.replace(watched, '#include "globals.h"\n'))
    path = write(tmp_path_factory, 'end = 4.25\n[[event]]\nat = 4.15\nkind = "set"\nvar = "mode"\nvalue = 2\n'
                 '[[event]]\nat = 4.15\nkind = "set"\nvar = "table"\nindex = 2\nvalue = 0.5\n')
    run = simulate(folder / "watch_inputs.c", str(path))
    assert run.lines() == ["gain 1.50 mode 0 table2 0.00 simu 0 0 0",
                           "gain 1.50 mode 2 table2 0.50 simu 0 0 0"]

    def listed(lab, *more):
        r = subprocess.run([sys.executable, "-m", "crslab", "vars", "--lab", str(lab), "--json", *more],
                           capture_output=True, text=True, timeout=120)
        return {row["name"]: row for row in json.loads(r.stdout)}

    rows = listed(folder / "watch_inputs.c")
    assert [(rows[n]["file"], rows[n]["line"], rows[n]["section"]) for n in ("gain", "mode", "table")] == \
        [("globals.h", 3, ".my_vars"), ("globals.h", 5, ".my_vars"), ("globals.h", 7, ".my_arrs")]
    # the lab's own globals keep their lines in the lab file
    lab_text = (folder / "watch_inputs.c").read_text()
    mycount = listed(folder / "watch_inputs.c", "--all")["mycount"]
    line = lab_text[:lab_text.index("long mycount")].count("\n") + 1
    assert (mycount["file"], mycount["line"]) == ("", line)
    # the same addresses as when the lab defines them itself: each first in its section in both
    alone = listed(LABS / "watch_inputs.c")
    assert {n: row["address"] for n, row in rows.items()} == {n: row["address"] for n, row in alone.items()}
