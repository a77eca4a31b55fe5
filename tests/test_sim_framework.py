"""The framework's tick as docs/framework.md section 3 describes it, shown on the simulated arm."""

from pathlib import Path

import numpy as np
import pytest

from crslab import crs
from crslab.plant.plant_params import PlantParams
from crslab.run.api import simulate

LABS = Path(__file__).parent / "labs"


@pytest.fixture(scope="module")
def open_loop():
    # no hand: the arm rests, then the lab's own torque turns joint 1
    return simulate(LABS / "open_loop_tau1.c", "hands_off", duration_s=6.0, log=True)


def test_first_lab_call_is_at_4_1_s():
    run = simulate(LABS / "persistent_tau.c", duration_s=4.2, log=True)
    assert run.calls[0][0] == 4100
    assert run.calls[0][1] == b"first call\n\r"
    at_once = simulate(LABS / "persistent_tau.c", duration_s=0.01, startup_delay=False)
    assert at_once.calls[0][0] == 0


def test_torques_persist_and_are_clamped():
    run = simulate(LABS / "persistent_tau.c", duration_s=4.5, log=True)
    log = run.log
    before = log["tick"][:, 0] < 4100
    assert np.all(log["tau_applied"][before] == 0.0)  # nothing reaches the motors before 4.1 s
    after = log["tick"][:, 0] >= 4100
    # written once, on the first call: 40 is applied as 5, tau2 keeps 0.5, tau3 was never written
    np.testing.assert_array_equal(log["tau_lab"][after][-1], [40.0, 0.5, 0.0])
    inside = after & (log["safety"][:, 0] == 0)
    assert inside.sum() > 100
    np.testing.assert_array_equal(np.unique(log["tau_applied"][inside], axis=0), [[5.0, 0.5, 0.0]])


def test_open_loop_tau1_leaves_the_envelope_and_is_held(open_loop):
    log = open_loop.log
    th1 = log["enc_rad"][:, 0]
    flag = log["safety"][:, 0]
    first_out = int(np.argmax(flag == 1))
    assert flag[first_out] == 1 and first_out > 0
    # it turned joint 1 positive until |th1 DH| passed 0.6667 pi (th1 DH = th1 motor)
    assert th1[first_out] > 0.6667 * np.pi
    assert np.all(th1[:first_out] <= 0.6667 * np.pi + 1e-6)
    # from then on the lab's +1.0 is ignored: the hold controller pushes back (negative)
    assert log["tau_applied"][first_out, 0] < 0
    # the lab hears about it in the next call: it printed the flag change with error = 1
    tick_out = int(log["tick"][first_out, 0])
    change = [(t, d) for t, d in open_loop.calls if d.startswith(b"error 1")]
    assert change and change[0][0] == tick_out + 1
    # it got there at the speed where friction takes the whole command: the course's line,
    # 1 unit = Cpos1 + Vpos1 w (params.toml), about 2.7 rad/s
    plant = PlantParams.defaults()
    terminal = (plant.motor_gain * 1.0 - plant.coulomb_pos_nm[0]) / plant.viscous_pos_nm_s_per_rad[0]
    speed = (th1[first_out] - th1[first_out - 10]) / 0.010
    assert speed == pytest.approx(terminal, rel=0.03)
    # held: the hold controller's 5 units stop the arm within a few hundredths of a radian past the
    # edge (0.048 on this arm), then re-anchored it is held there
    overshoot = th1.max() - 0.6667 * np.pi
    assert 0.02 < overshoot < 0.06
    assert np.ptp(th1[-500:]) < 1e-3 and 0.0 < th1[-1] - 0.6667 * np.pi < overshoot


def test_encoders_are_quantized_and_offset():
    run = simulate(duration_s=4.2, log=True)
    enc = run.log["enc_rad"][-1]
    counts = enc / (np.pi / 144000)
    # motor 1 has no offset, so its reading is a whole number of counts
    assert abs(counts[0] - round(counts[0])) < 1e-3
    # with the lab's offsets equal to the true rest pose, the reading is the true motor angle
    true_motor = crs.dh_to_motor(run.log["qpos_dh_rad"][-1])
    np.testing.assert_allclose(enc, true_motor, atol=np.pi / 144000 + 1e-6)


def test_wrong_offsets_print_wrong_angles():
    run = simulate(duration_s=4.2, rest_motor_rad=(0.0, -0.30, 0.10))
    first = [float(v) for v in run.lines()[0].split()]
    # the lab assumes rest at (-0.42, 0.24) rad, the arm rests at (-0.30, 0.10): it prints the assumption
    np.testing.assert_allclose(first, np.degrees([0, -0.42, 0.24]), atol=0.01)
