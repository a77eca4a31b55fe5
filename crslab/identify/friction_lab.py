"""Running crslab's Lab 3 friction identification (``csrc/labs/lab3_friction_id.c``) on crslab's arm.

The lab runs from its first tick (no startup delay: the real board's first 4.1 s change nothing
for it) in the sandboxed worker, as any lab does, until it prints ``done``; which joints and
speeds it measures are its watched variables ``measure_joint`` and ``speeds_rad_s``, set before
the first tick. What it printed is the identification's data (:func:`parse_points`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from crslab.framework_facts import TICKS_PER_S
from crslab.identify.friction_table import LAB_SPEEDS_RAD_S, Point, parse_points
from crslab.plant.plant_params import PlantParams
from crslab.resources import path as resource_path

FRICTION_LAB = resource_path("csrc", "labs", "lab3_friction_id.c")
"""crslab's Lab 3 friction identification lab."""
MAX_SPEEDS = 9
"""The most speeds the lab holds (its ``NSPEEDS``)."""
SLICE_S = 20.0
"""The run is checked for ``done`` this often (simulated seconds)."""


WATCHED = ("n_speeds", "speeds_rad_s", "measure_joint")
"""The watched variables crslab sets before the first tick: a lab must have them."""


class FrictionRunError(RuntimeError):
    """The lab did not finish its identification; the message says why."""


class NotAFrictionLab(ValueError):
    """The lab lacks the watched variables crslab drives the identification with."""


@dataclass(frozen=True)
class FrictionRun:
    """What one run gave: every pass's point, the lab's transcript, and how long it ran (s)."""

    points: list[Point]
    transcript: str
    simulated_s: float


def lab_duration_s(speeds_rad_s: Sequence[float], joints: Sequence[int]) -> float:
    """A generous bound on how long the lab takes (simulated s): both passes at every speed over
    each joint's sweep, the pauses, the moves between poses.

    >>> round(lab_duration_s(LAB_SPEEDS_RAD_S, (1, 2, 3)))
    415
    """
    sweep = {1: 1.2, 2: 1.2, 3: 0.8}  # twice the lab's sweep_rad: one pass, rad
    per_joint = {j: sum(2 * (sweep[j] / s + 0.3) for s in speeds_rad_s) + 6.0 for j in joints}
    return 1.25 * (sum(per_joint.values()) + 8.0) + 15.0


def run_friction_lab(plant: PlantParams | None = None, *, joints: Sequence[int] = (1, 2, 3),
                     speeds_rad_s: Sequence[float] = LAB_SPEEDS_RAD_S, lab: str | Path = FRICTION_LAB,
                     sandbox: bool | None = None,
                     on_progress: Callable[[float, float], None] | None = None) -> FrictionRun:
    """Run the Lab 3 lab on crslab's arm with ``plant`` (default: crslab's) measuring ``joints`` at
    ``speeds_rad_s``; ``on_progress(simulated_s, bound_s)`` after every slice. Raises
    :class:`FrictionRunError` when the run fails or the lab never says ``done``,
    :class:`NotAFrictionLab` for a lab without the variables crslab sets."""
    from crslab.run.assemble import make_config, started
    from crslab.run.board_run import RunError
    from crslab.sinks.memory import MemorySink

    speeds = [float(s) for s in speeds_rad_s]
    if not 2 <= len(speeds) <= MAX_SPEEDS or any(s <= 0 for s in speeds):
        raise FrictionRunError(f"give 2 to {MAX_SPEEDS} motor speeds above 0 rad/s, got {speeds}")
    if not joints or any(j not in (1, 2, 3) for j in joints):
        raise FrictionRunError(f"joints are 1, 2 and 3, got {list(joints)}")
    config = make_config(lab, "hands_off", startup_delay=False, plant=plant or PlantParams.defaults(),
                         sandbox=sandbox)
    missing = [name for name in WATCHED if name not in {v.name for v in config.build.watched}]
    if missing:
        raise NotAFrictionLab(f"{Path(lab).name} does not watch {', '.join(missing)} (#pragma DATA_SECTION): "
                              f"not a Lab 3 friction lab crslab can drive")
    bound = lab_duration_s(speeds, joints)
    memory = MemorySink()
    tick, end = 0, int(bound * TICKS_PER_S)
    try:
        with started(config) as sim:
            sim.set("n_speeds", float(len(speeds)))
            for i, s in enumerate(speeds):
                sim.set("speeds_rad_s", s, index=i)
            for j in (1, 2, 3):
                sim.set("measure_joint", 1.0 if j in joints else 0.0, index=j - 1)
            while tick < end:
                tick = min(end, tick + int(SLICE_S * TICKS_PER_S))
                result = sim.run(tick, memory)
                if not result.ok:
                    raise FrictionRunError(result.message or str(result.status))
                if on_progress is not None:
                    on_progress(tick / TICKS_PER_S, bound)
                if b"done" in memory.transcript:
                    break
    except RunError as exc:
        raise FrictionRunError(str(exc)) from None
    text = memory.transcript.decode("ascii", "replace")
    done = [t for t, data in memory.calls if b"done" in data]
    if not done:
        raise FrictionRunError(f"{Path(lab).name} did not finish within {bound:.0f} s (no 'done')")
    return FrictionRun(parse_points(text), text, done[0] / TICKS_PER_S)
