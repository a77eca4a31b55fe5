"""The built-in scenarios do what `crslab scenarios` says, with labs written for them."""

from pathlib import Path

import numpy as np
import pytest

from crslab.scenario.load import ScenarioError
from crslab.sim.api import simulate

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


def test_end_mass_payload_is_held_at_rest_then_changes_the_response(steps):
    plain, loaded = steps
    a, b = angles(plain), angles(loaded)
    np.testing.assert_allclose(b[:9], [[0, -0.42, 0.24]] * 9, atol=0.01)    # held until 5 s
    # while the hand holds the arm at rest the PD lab asks 60 * 0.42 = 25 units of joint 2 (the
    # clamp's 5 reach the Piccolo motor board, beyond its 4): 500 ms after the first call (tick
    # 4600) the board cuts every output, until joint 2's command drops after the release at 5 s.
    # The unloaded arm reaches its target within those 500 ms: no cut-out.
    assert plain.stats["motor_board_events"] == []
    cut, back = loaded.stats["motor_board_events"]
    assert cut == (4600, 2, 1) and back[1:] == (2, 0) and 5000 < back[0] < 5200
    # released, the loaded forearm sags past the envelope's th3 <= 2.3 rad and the framework's hold
    # controller keeps it just beyond (within its 0.15 rad re-anchoring): the lab's steps between
    # 0 and pi/6 never reach the arm again, while the unloaded arm follows them
    th3 = loaded.log["qpos_dh_rad"][:, 2]
    assert 2.3 < th3[-1] < 2.3 + 0.15 and np.all(loaded.log["safety"][-6000:, 0] == 1)
    np.testing.assert_allclose(b[-60:], [b[-1]] * 60, atol=0.002)
    assert np.all(plain.log["safety"][:, 0] == 0)
    np.testing.assert_allclose([a[-11], a[-1]], [[0.0] * 3, [np.pi / 6] * 3], atol=0.03)
