"""The friction model's rules (models/crs_arm/README.md, "Friction"), on the simulated arm as a lab
sees it: a joint sticks while the torque on it stays within its static band [Sneg, Spos]; beyond
it the joint slides, and at a steady speed w the torque it takes is the course's line, Cpos + Vpos w
moving positive, Cneg + Vneg w moving negative (crslab's Lab 3 lab measures it); left alone at
its resting pose it does not creep (tests/test_plant_fidelity.py runs the 10 minutes)."""

from pathlib import Path

import numpy as np
import pytest

from crslab.identify.friction_lab import run_friction_lab
from crslab.plant.model import holding_torques_nm
from crslab.plant.model_files import REST_MOTOR_RAD
from crslab.plant.plant_params import PlantParams
from crslab.run.api import make_config
from crslab.run.board_run import BoardRun
from crslab.sinks.memory import MemorySink

LABS = Path(__file__).parent / "labs"
COUNT_RAD = np.pi / 144000


def moved(plant: PlantParams, tau_units, seconds: float) -> np.ndarray:
    """How far each motor angle moved (rad) with the constant torques ``tau_units`` from the first
    tick, starting at rest in the resting pose."""
    config = make_config(LABS / "constant_torque.c", "hands_off", startup_delay=False, log=True, plant=plant)
    memory = MemorySink()
    with BoardRun(config) as sim:
        for j, u in enumerate(tau_units):
            sim.set("tau_units", float(u), index=j)
        sim.run(int(seconds * 1000), memory)
    enc = memory.log["enc_rad"]
    return enc[-1] - enc[0]


@pytest.mark.parametrize("motor", [1, 2, 3])
def test_a_joint_sticks_while_the_torque_on_it_stays_within_its_static_band(motor):
    """Gravity's own push at the resting pose (what holding_torques_nm reverses) plus the motor's
    torque: 97 % of the way to either edge of the band nothing moves (not one encoder count in 2 s);
    5 % past it the joint slides that way."""
    plant = PlantParams.defaults()
    gravity_push = -holding_torques_nm(REST_MOTOR_RAD, plant)[motor - 1]
    for edge, sign in ((plant.static_pos_nm[motor - 1], 1), (plant.static_neg_nm[motor - 1], -1)):
        tau = np.zeros(3)
        tau[motor - 1] = (0.97 * edge - gravity_push) / plant.motor_gain
        still = moved(plant, tau, 2.0)
        assert np.all(np.abs(still) < COUNT_RAD), (edge, still)
        tau[motor - 1] = (1.05 * edge - gravity_push) / plant.motor_gain
        slid = moved(plant, tau, 1.0)
        assert sign * slid[motor - 1] > 50 * COUNT_RAD, (edge, slid)


def test_a_wider_band_holds_what_the_shipped_one_lets_slide():
    """The band is the plant's, not a constant: motor 1 at 1.05 Spos slides on crslab's arm and
    holds when the static friction is raised 10 %."""
    plant = PlantParams.defaults()
    tau = [1.05 * plant.static_pos_nm[0] / plant.motor_gain, 0.0, 0.0]
    assert moved(plant, tau, 1.0)[0] > 50 * COUNT_RAD
    stiffer = plant.with_values({"static_pos1": 1.1 * plant.static_pos_nm[0]})
    assert abs(moved(stiffer, tau, 1.0)[0]) < COUNT_RAD


@pytest.fixture(scope="module")
def lab3_points():
    """A short run of crslab's Lab 3 lab: three speeds each way, every joint (about 70 s simulated)."""
    return run_friction_lab(speeds_rad_s=(0.15, 0.6, 1.5)).points


def test_sliding_at_a_steady_speed_takes_the_course_lines(lab3_points):
    """Each pass's mean command is the plant's friction at its speed over the motor gain: the static
    band's edge risen to the line Cpos + Vpos w (Cneg + Vneg w moving negative), computed here by
    PlantParams.friction_nm in Python, independently of the board's C (csrc/plant/friction.c)."""
    plant = PlantParams.defaults()
    assert len(lab3_points) == 18
    for p in lab3_points:
        expected = plant.friction_nm(p.joint, p.speed_rad_s) / plant.motor_gain
        assert abs(p.speed_rad_s) == pytest.approx(round(abs(p.speed_rad_s), 2), abs=0.005)
        assert p.command_units == pytest.approx(expected, rel=0.005), p
    # and well above the transition speed that is the line itself (exp(-7.5) of the gap left)
    m = 0
    line = plant.coulomb_pos_nm[m] + plant.viscous_pos_nm_s_per_rad[m] * 0.6
    fast = [p for p in lab3_points if p.joint == 1 and p.speed_rad_s > 0.5]
    assert fast[0].command_units * plant.motor_gain == pytest.approx(line, rel=0.005)


def test_the_lines_move_with_the_plants_friction(lab3_points):
    """Doubling joint 2's friction (a sweep's friction2 = 2) doubles what each of its passes takes."""
    plant = PlantParams.defaults().with_values({"friction2": 2.0})
    doubled = run_friction_lab(plant, joints=(2,), speeds_rad_s=(0.15, 0.6, 1.5)).points
    base = [p for p in lab3_points if p.joint == 2]
    assert [round(p.speed_rad_s, 2) for p in doubled] == [round(p.speed_rad_s, 2) for p in base]
    for d, b in zip(doubled, base):
        assert d.command_units == pytest.approx(2.0 * b.command_units, rel=0.01)
