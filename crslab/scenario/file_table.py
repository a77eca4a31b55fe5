"""The fields several tables of a scenario file share (a hand's target, joints, per-joint values,
an end mass), each read from one table of the file (the top level, ``[plant]`` or one
``[[event]]``: a :class:`crslab.toml_file.Table`, whose errors name the file, the line and the key)."""

from __future__ import annotations

import numpy as np

from crslab import crs
from crslab.plant.model_files import COURSE_END_MASS_KG
from crslab.toml_file import Table

MAX_END_MASS_KG = 10.0
"""The most mass a scenario may clamp at the end effector, kg (the course's is 1.54 kg)."""
MAX_FRICTION_SCALE = 100.0
"""The most a scenario may scale the arm's friction."""
MAX_PUSH_N = 1000.0
"""The largest component of a push, N."""


class ScenarioError(ValueError):
    """A scenario that cannot be used; the message names file, line and key."""


def hand_target(r: Table) -> tuple[float, float, float] | None:
    given = [k for k in ("motor_deg", "dh_deg", "xyz_in", "pose") if k in r.table]
    if len(given) != 1:
        raise r.fail("motor_deg|dh_deg|xyz_in|pose", "give exactly one target")
    key = given[0]
    if key == "pose":
        if r.table[key] != "rest":
            raise r.fail(key, f"the only named pose is \"rest\", got {r.table[key]!r}")
        return None
    v = r.triple(key)
    if key == "dh_deg":
        dh = np.radians(v)
    elif key == "motor_deg":
        dh = crs.motor_to_dh(np.radians(v))
    else:
        q, status = crs.ik_with_status(v, elbow="up")
        if int(status) != crs.IK_OK:
            raise r.fail(key, f"target {v.tolist()} in is {crs.IK_STATUS_TEXT[int(status)]}")
        dh = crs.motor_to_dh(q)
    return (float(dh[0]), float(dh[1]), float(dh[2]))


def joint_numbers(r: Table) -> tuple[int, ...]:
    """``joint = N`` or ``joints = [..]`` (numbers 1..3); all three when neither is given."""
    if "joint" in r.table and "joints" in r.table:
        raise r.fail("joints", "give joint or joints, not both")
    if "joint" in r.table:
        return (r.integer("joint", minimum=1, maximum=3),)
    if "joints" not in r.table:
        return (1, 2, 3)
    value = r.table["joints"]
    if (not isinstance(value, list) or not value
            or not all(isinstance(j, int) and not isinstance(j, bool) and 1 <= j <= 3 for j in value)):
        raise r.fail("joints", f"must be a list of joint numbers 1..3, got {value!r}")
    return tuple(sorted(set(value)))


def per_joint(r: Table, key: str, *, whole: bool, minimum: float | None = None) -> tuple[float, ...]:
    """``key`` as three values: a list of three, or one number for ``joint``/``joints``."""
    if key not in r.table:
        raise r.fail(key, "missing")
    value = r.table[key]
    if isinstance(value, list):
        if "joint" in r.table or "joints" in r.table:
            raise r.fail(key, "a list gives every joint its value: leave out joint/joints")
        values = list(r.triple(key))
        raw = value
    else:
        r.number(key, minimum=minimum)
        joints = joint_numbers(r)
        values = [float(value) if j + 1 in joints else 0.0 for j in range(3)]
        raw = [value]
    if whole and not all(isinstance(v, int) for v in raw):
        raise r.fail(key, f"must be whole numbers of counts, got {value!r}")
    if minimum is not None and any(v < minimum for v in values):
        raise r.fail(key, f"must be at least {minimum:g}, got {value!r}")
    return tuple(values)


def end_mass_kg(r: Table, key: str) -> float:
    value = r.table.get(key)
    if value == "course":
        return COURSE_END_MASS_KG
    if isinstance(value, str):
        raise r.fail(key, f"must be a number of kg or \"course\", got {value!r}")
    return r.number(key, minimum=0.0, maximum=MAX_END_MASS_KG)
