"""Lab 3 with the course's added end mass: a Lab 3-style inverse-dynamics controller built on the
course's p vector for the end mass holds the mass where it is told to; built on the bare arm's p
vector, the forearm sags by the gravity it does not know about, as the lab shows students."""

import sys
from pathlib import Path

import numpy as np
import pytest

from crslab.plant.plant_params import PlantParams

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools" / "benchmarks"))
from lab3_end_mass import KP, P_BARE, P_MASS, TARGET, G, hold  # noqa: E402


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
