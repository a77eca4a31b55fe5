"""The Lab 3 end-mass experiment the fidelity benchmark prints and tests/test_lab3_end_mass.py
checks: tests/labs/lab3_inverse_dynamics.c (inverse dynamics on the course's p vector) holding the
arm at its target with the course's added end mass on, built on the p vector for the mass or on the
bare arm's."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from crslab.run.api import make_config
from crslab.run.assemble import started
from crslab.sinks.memory import MemorySink

LAB = Path(__file__).resolve().parents[2] / "tests" / "labs" / "lab3_inverse_dynamics.c"
G = 9.81
P_BARE = (0.0300, 0.0128, 0.0076, 0.0753, 0.0298)
P_MASS = (0.0466, 0.0388, 0.0284, 0.1405, 0.1298)
TARGET = (0.3, 0.0, 0.2)  # the lab's target, motor angles (rad); the upper arm upright
KP = 2500.0               # its outer loop's gain, rad/s^2 per rad


def hold(use_mass_p: bool) -> np.ndarray:
    """The lab on the end_mass scenario (the mass on from the start, lab() from 4.1 s); its last
    printed line, 8 s in: the three motor angles and the torques on motors 2 and 3. Raises
    RuntimeError when the run did not hold the arm (a cut-out, the envelope, still moving)."""
    config = make_config(LAB, "end_mass", log=True)
    memory = MemorySink()
    with started(config) as sim:
        sim.set("use_mass_p", 1.0 if use_mass_p else 0.0)
        result = sim.run(12100, memory)
    if not result.ok or result.stats.motor_board_events or memory.log["safety"].any():
        raise RuntimeError(f"the end-mass run did not hold the arm: {result.message or result.stats}")
    rows = np.array([[float(v) for v in d.split()] for _, d in memory.calls])
    if len(rows) != 80 or np.ptp(rows[-20:, :3], axis=0).max() >= 1e-4:  # at rest for its last 2 s
        raise RuntimeError("the end-mass run did not come to rest")
    return rows[-1]
