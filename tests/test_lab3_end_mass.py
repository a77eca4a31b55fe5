"""Lab 3 with the course's added end mass: a Lab 3-style inverse-dynamics controller built on the
course's p vector for the end mass holds the mass where it is told to; built on the bare arm's p
vector, the forearm sags by the gravity it does not know about, as the lab shows students."""

from pathlib import Path

import numpy as np
import pytest

from crslab.plant.plant_params import PlantParams
from crslab.sim.api import make_config
from crslab.sim.session import Simulation
from crslab.sinks.memory import MemorySink

LAB = Path(__file__).parent / "labs" / "lab3_inverse_dynamics.c"
G = 9.81
P_BARE = (0.0300, 0.0128, 0.0076, 0.0753, 0.0298)
P_MASS = (0.0466, 0.0388, 0.0284, 0.1405, 0.1298)
TARGET = (0.3, 0.0, 0.2)  # the lab's target, motor angles (rad); the upper arm upright
KP = 2500.0               # its outer loop's gain, rad/s^2 per rad


def hold(use_mass_p: bool) -> np.ndarray:
    """The lab on the end_mass scenario (the mass on from the start, lab() from 4.1 s); its last
    printed line, 8 s in: the three motor angles and the torques on motors 2 and 3."""
    config = make_config(LAB, "end_mass", log=True)
    memory = MemorySink()
    with Simulation(config) as sim:
        sim.set("use_mass_p", 1.0 if use_mass_p else 0.0)
        result = sim.run(12100, memory)
    assert result.ok and result.stats["motor_board_events"] == []
    assert not memory.log["safety"].any()  # never outside the safety envelope
    rows = np.array([[float(v) for v in d.split()] for _, d in memory.calls])
    assert len(rows) == 80 and np.ptp(rows[-20:, :3], axis=0).max() < 1e-4  # at rest for 2 s
    return rows[-1]


@pytest.fixture(scope="module")
def held():
    return {True: hold(True), False: hold(False)}


def test_with_the_course_p_vector_for_the_end_mass_the_arm_holds_the_mass_where_told(held):
    """Gravity is the course's (tests/test_crs_model.py: within 5 % over the workspace), so what is
    left is friction: the forearm rests where the PD term p2 Kp e stays inside motor 3's static
    band, a few thousandths of a radian."""
    plant = PlantParams.defaults()
    band = max(abs(v) for v in plant.static_band_nm(3)) / plant.motor_gain  # units
    err = held[True][:3] - TARGET
    assert abs(err[2]) <= band / (P_MASS[1] * KP) + 1e-4
    assert abs(err[2]) < 0.006 and abs(err[1]) < 0.006
    # the lab's torque on motor 3 is the course's gravity for the mass and that PD term
    gravity = -P_MASS[4] * G * np.cos(held[True][2])
    assert held[True][4] == pytest.approx(gravity + P_MASS[1] * KP * -err[2], abs=0.01)


def test_with_the_bare_arms_p_vector_the_forearm_sags_by_the_unknown_gravity(held):
    """Held still, the outer loop supplies what G misses: p2 Kp e = (p5_mass - p5_bare) g cos th3
    (motor 3; motor 2 is upright, sin th2 = 0), give or take motor 3's static band over p2 Kp: a
    sag of 0.030 rad, the payload's gravity in the controller's eyes."""
    plant = PlantParams.defaults()
    band = max(abs(v) for v in plant.static_band_nm(3)) / plant.motor_gain
    missing = (P_MASS[4] - P_BARE[4]) * G * np.cos(TARGET[2])
    sag = held[False][2] - TARGET[2]
    assert sag == pytest.approx(missing / (P_BARE[1] * KP), abs=band / (P_BARE[1] * KP))
    assert sag > 0.02 and sag > 4 * abs(held[True][2] - TARGET[2])
