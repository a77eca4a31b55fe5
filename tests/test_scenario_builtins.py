"""The built-in scenarios do what `crslab scenarios` says, with labs written for them."""

from pathlib import Path

import numpy as np
import pytest

from crslab.plant.model import holding_torques_nm
from crslab.plant.model_files import COURSE_END_MASS_KG
from crslab.plant.plant_params import PlantParams
from crslab.run.api import simulate
from crslab.scenario.load import ScenarioError

LABS = Path(__file__).parent / "labs"


def numbers_at(run, t_s, line=0):
    """The numbers of line ``line`` of the print made at t_s."""
    rows = [d for tick, d in run.calls if tick == round(t_s * 1000)]
    return np.array([float(v) for v in rows[line].split(b":")[-1].split()])


def test_lab1_offsets_right_offsets_print_the_known_poses():
    run = simulate(None, "lab1_offsets")
    np.testing.assert_allclose(numbers_at(run, 4.1), np.degrees([0, -0.42, 0.24]), atol=0.01)  # at rest
    np.testing.assert_allclose(numbers_at(run, 10.6), [0, 0, 0], atol=0.02)                   # motor zero
    np.testing.assert_allclose(numbers_at(run, 14.6), [0, 90, 0], atol=0.3)                   # DH zero
    np.testing.assert_allclose(numbers_at(run, 16.6), np.degrees([0, -0.42, 0.24]), atol=0.05)


def test_lab1_offsets_wrong_offsets_show_at_motor_zero():
    run = simulate(None, "lab1_offsets", rest_motor_rad=(0.0, -0.37, 0.27), duration_s=10.7)
    # the arm rested at the template's (-0.37, 0.27); the lab believes (-0.42, 0.24)
    np.testing.assert_allclose(numbers_at(run, 10.6), np.degrees([0, -0.05, -0.03]), atol=0.02)


@pytest.fixture(scope="module")
def torque_signs():
    return simulate(LABS / "torque_signs.c", "lab1_torque_signs")


@pytest.mark.parametrize("joint, start_s", [(1, 5.0), (2, 8.0), (3, 11.0)])
def test_lab1_torque_signs_drive_one_joint_at_a_time_positive(torque_signs, joint, start_s):
    before = numbers_at(torque_signs, start_s - 0.25 + 0.1)
    after = numbers_at(torque_signs, start_s + 0.5 + 0.1)   # 0.5 s of +1 unit, then 0
    during = next(d for t, d in torque_signs.calls if t == round((start_s + 0.1) * 1000))
    assert during.startswith(f"joint {joint}:".encode())             # the lab saw the write
    moved = after - before
    assert moved[joint - 1] > 2.0                                    # degrees, positive
    others = np.delete(moved, joint - 1)
    assert np.all(np.abs(others) < 0.5 * moved[joint - 1])
    back = numbers_at(torque_signs, start_s + 2.6)                   # the hand put it back to rest
    np.testing.assert_allclose(back, np.degrees([0, -0.42, 0.24]), atol=0.1)


def test_lab1_torque_signs_needs_a_lab_that_watches_torquejoint():
    with pytest.raises(ScenarioError, match=r"lab1_torque_signs.toml:\d+: var: torquejoint is not a watched"):
        simulate(None, "lab1_torque_signs")


def angles(run):
    return np.array([[float(v) for v in d.split()] for _, d in run.calls])


@pytest.fixture(scope="module")
def steps():
    return (simulate(LABS / "pd_steps.c", "lab2_steps", log=True),
            simulate(LABS / "pd_steps.c", "end_mass", log=True))


def test_lab2_steps_the_pd_lab_steps_between_0_and_pi_over_6(steps):
    run, _ = steps
    a = angles(run)  # every 100 ms from 4.1 s; targets: 0 for 1 s, pi/6 for 1 s, ...
    assert run.calls[-1][0] == 12000 and len(a) == 80
    at_zero, at_step = a[9], a[19]    # the end of the first 0 and pi/6 seconds
    np.testing.assert_allclose(at_zero, 0, atol=0.03)
    np.testing.assert_allclose(at_step, np.pi / 6, atol=0.03)


def test_end_mass_payload_is_held_at_rest_then_sags_by_gravitys_share(steps):
    plain, loaded = steps
    a, b = angles(plain), angles(loaded)
    np.testing.assert_allclose(b[0], [0, -0.42, 0.24], atol=0.01)    # held at rest until 4.1 s
    # the hand lets go as lab() takes over: no fight between them, so no motor-board cut-out and
    # the arm never leaves the envelope, loaded or not
    assert plain.stats.motor_board_events == () and loaded.stats.motor_board_events == ()
    assert np.all(plain.log["safety"][:, 0] == 0) and np.all(loaded.log["safety"][:, 0] == 0)
    # both follow the steps between 0 and pi/6 (every 100 ms from 4.1 s; the last sample of each
    # 1 s step settled), and come to rest where friction holds them: motor 3, which carries the
    # forearm and the payload, comes to rest (or to a creep far slower than friction's transition
    # speed) where the lab's Kp (target - angle) plus gravity's push lies within what friction can
    # take at rest: its static band [Sneg3, Spos3], or up to its lines' intercepts [Cneg3, Cpos3]
    # while it creeps. The payload's gravity (0.85-0.98 units more) moves that window by about a
    # band's width: the loaded arm rests lower on the forearm. (The printed angles have 3 decimals:
    # 0.0005 rad is 0.03 units of Kp.)
    plant = PlantParams.defaults()
    loaded_plant = plant.with_values({"payload_kg": COURSE_END_MASS_KG})
    low = min(plant.static_neg_nm[2], plant.coulomb_neg_nm[2]) / plant.motor_gain
    high = max(plant.static_pos_nm[2], plant.coulomb_pos_nm[2]) / plant.motor_gain
    kp = 60.0                                                              # pd_steps.c's Kp, units/rad
    for target, settled in ((0.0, 69), (np.pi / 6, 79)):          # at 10.9 s and 11.9 s
        pose = [target] * 3
        np.testing.assert_allclose(a[settled], pose, atol=0.03)
        for arm, rest in ((plant, a[settled]), (loaded_plant, b[settled])):
            push = -holding_torques_nm(rest, arm)[2] / plant.motor_gain      # gravity on motor 3, units
            held = kp * (target - rest[2]) + push
            assert low - 0.035 <= held <= high + 0.035, (target, arm.payload_kg, held, low, high)
        assert b[settled][2] > a[settled][2] - 0.002
