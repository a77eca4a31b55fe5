"""The CRS arm model's files (``models/crs_arm``) and the numbers of its ``params.toml``, without
importing MuJoCo: the crslab process reads these; only the worker loads the model (the values a
run uses, a plant file's or a sweep's included, are :mod:`crslab.plant.plant_params`').

>>> REST_MOTOR_RAD
(0.0, -0.42, 0.24)
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from crslab import resources

MODEL_DIR: Path = resources.path("models", "crs_arm")
"""Folder of the CRS arm model (the repository's ``models/crs_arm``, shipped with the package)."""
SCENE_XML: Path = MODEL_DIR / "scene.xml"
"""The scene to simulate: the arm, the 1 ms timestep, gravity, a floor and a light."""
ARM_XML: Path = MODEL_DIR / "crs_arm.xml"
"""The robot alone (included by the scene)."""
PARAMS_TOML: Path = MODEL_DIR / "params.toml"
"""The physical parameters the model is generated from."""

with PARAMS_TOML.open("rb") as _f:
    PARAMS: dict = tomllib.load(_f)
"""``params.toml`` as a dict (read-only by convention)."""

_REST = PARAMS["rest_motor_rad"]
REST_MOTOR_RAD: tuple[float, float, float] = (float(_REST["th1"]), float(_REST["th2"]), float(_REST["th3"]))
"""Default true resting motor angles (rad): the pose the encoders are zeroed in (docs/framework.md
section 3)."""

NEWTON_METRE_PER_UNIT: float = float(PARAMS["command"]["newton_metre_per_unit"])
"""Joint torque of one course command unit (N.m), the actuators' gear."""

COURSE_END_MASS_KG: float = float(PARAMS["payload"]["course_end_mass"])
"""The course's added end mass (kg) as implied by its identified p vectors (models/crs_arm/README.md)."""

