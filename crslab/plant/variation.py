"""How one arm differs from the identified model: friction per motor, the links' masses and the
drives' gain (N.m per command unit), applied to the MuJoCo model before the first tick.

This is what ``crslab sweep`` varies on today's plant (``crslab/sweep/variations.py`` maps its
names here). A scenario's later ``friction`` events scale the friction of *this* arm.

>>> import mujoco
>>> from crslab.plant.model import load_model
>>> model = load_model(); data = mujoco.MjData(model)
>>> PlantVariation(friction_scale=(1.0, 2.0, 1.0), motor_gain=0.5).apply_to(model, data)
>>> float(model.dof_frictionloss[1]), float(model.actuator_gear[0, 0])
(5.874, 3.0)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # the crslab process never loads MuJoCo: only the worker applies a variation
    import mujoco

IDENTITY_SCALES = (1.0, 1.0, 1.0)


@dataclass(frozen=True)
class PlantVariation:
    """Scales relative to the identified model (1 leaves it as it is).

    ``friction_scale[j]``: frictionloss and damping of motor j + 1 (motor 3 acts on the forearm
    tendon, so its scale covers the tendon and joint 3); ``mass_scale``: mass and inertia of every
    link (not the payload, which ``end_mass`` sets); ``motor_gain``: joint torque per command unit.
    """

    friction_scale: tuple[float, float, float] = IDENTITY_SCALES
    mass_scale: float = 1.0
    motor_gain: float = 1.0

    @property
    def is_identity(self) -> bool:
        """True when the variation changes nothing."""
        return self == PlantVariation()

    def apply_to(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Change ``model`` in place (before the first step); ``data`` is scratch for MuJoCo's
        derived constants."""
        if self.is_identity:
            return
        import mujoco

        from crslab.plant.model import PAYLOAD_BODY

        s1, s2, s3 = self.friction_scale
        dof = np.array([s1, s2, s3])
        model.dof_frictionloss[:3] *= dof
        model.dof_damping[:3] *= dof
        model.tendon_frictionloss[:] *= s3
        model.tendon_damping[:] *= s3
        payload = model.body(PAYLOAD_BODY).id
        links = [b for b in range(1, model.nbody) if b != payload]
        model.body_mass[links] *= self.mass_scale
        model.body_inertia[links] *= self.mass_scale
        model.actuator_gear[:, 0] *= self.motor_gain
        mujoco.mj_setConst(model, data)  # subtree masses, inverse weights: from the new masses
