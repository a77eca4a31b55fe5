"""The real-arm recording the plant was fitted to, and what the fidelity numbers are judged by.

The recording (``lab2_square_pid_real.csv``, a real CRS arm's Simulink scope of
csrc/labs/lab2_square_pid.c) is the project's shared reference material, kept beside the
repository, not in it: ``$CRSLAB_REAL_DIR`` names its folder, else the first ``shared/real`` folder
found beside the checkout or one of its parents. :data:`REAL_RECORDING` is None when there is none.
"""

from __future__ import annotations

import os
from pathlib import Path

NAME = "lab2_square_pid_real.csv"
ROOT = Path(__file__).resolve().parents[2]


def find() -> Path | None:
    """The recording's path, or None."""
    env = os.environ.get("CRSLAB_REAL_DIR")
    folders = [Path(env)] if env else [p / "shared" / "real" for p in (ROOT, *ROOT.parents)]
    return next((f / NAME for f in folders if (f / NAME).is_file()), None)


REAL_RECORDING = find()

# The issue-12 targets, per joint, on this recording aligned over its 10 s.
TARGET_RMS_RAD = 0.015
TARGET_RISE_SHARE = 0.10       # rise time within 10 % of the real one
TARGET_PEAK_SPEED_SHARE = 0.15  # peak speed within 15 % of the real one
TARGET_ERROR_RAD = 0.005       # steady-state error within 0.005 rad of the real one

BEFORE_PLANT = Path(__file__).resolve().parent / "plant_before_issue12.toml"
"""The arm as crslab had it before the drive model (issue 12): the course's friction table, no drive."""
