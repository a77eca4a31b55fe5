"""The paragraph ``crslab sim`` prints on stderr before the first tick, so that a first run
explains itself: which lab, which scenario, at what pace, what the printed columns are when the
lab is one of crslab's own. ``--quiet`` leaves it out; it never reaches stdout or the transcript.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

from crslab import resources
from crslab.sinks.narration import seconds

PREFIX = "crslab sim: "
WIDTH = 100

OWN_LABS = {
    "lab1_kinematics.c": "crslab's own Lab 1 prints three lines twice a second: the motor angles theta1 "
    "theta2 theta3 (deg); the end effector's x y z (in) from forward kinematics; the motor angles (deg) "
    "inverse kinematics finds for that x y z (the first line again).",
    "lab2_tracking.c": "crslab's own tracking lab prints one line twice a second: the desired motor angles, "
    "the measured ones and their difference (deg).",
    "lab2_square_pid.c": "crslab's calibration lab (the controller of the real recording the arm was fitted "
    "to) steps every joint between 0 and pi/6 rad each second and prints twice a second: the three "
    "references, then the three motor angles (rad).",
}
"""What crslab's own lab files print, by file name (csrc/labs/)."""


def own_lab_note(source: Path) -> str | None:
    """What the columns are, when ``source`` is one of crslab's own labs (not a copy of one).

    >>> own_lab_note(resources.path("csrc", "labs", "lab1_kinematics.c")).split(":")[0]
    "crslab's own Lab 1 prints three lines twice a second"
    >>> own_lab_note(Path("mylab.c")) is None
    True
    """
    for name, note in OWN_LABS.items():
        own = resources.path("csrc", "labs", name)
        if Path(source).resolve() == own.resolve():
            return note
    return None


def pace_text(speed: float | None) -> str:
    """How fast the run goes, in words.

    >>> pace_text(None), pace_text(1.0), pace_text(2.5)
    ('as fast as it can', 'at real time', 'at 2.5x real time')
    """
    if speed is None:
        return "as fast as it can"
    return "at real time" if speed == 1.0 else f"at {speed:g}x real time"


def introduction(*, lab: Path, scenario_name: str, scenario_description: str, end_tick: int,
                 startup_ticks: int, speed: float | None, console: bool,
                 waypoints: Path | None = None) -> str:
    """The paragraph printed before the first tick (lines end in newlines).

    >>> print(introduction(lab=Path("mylab.c"), scenario_name="hands_off", scenario_description="",
    ...                    end_tick=30000, startup_ticks=4100, speed=None, console=False), end="")
    crslab sim: mylab.c on scenario hands_off for 30.0 s, as fast as it can.
      The framework calls lab() every 1 ms from t = 4.1 s; what the lab prints follows on stdout
      exactly as Tera Term shows it. Scenario events are announced here as they happen (--quiet: no
      notes).
    """
    head = f"{PREFIX}{lab.name} on scenario {scenario_name} for {seconds(end_tick)} s, {pace_text(speed)}."
    if waypoints is not None:
        head = f"{PREFIX}{lab.name} following {waypoints.name} for {seconds(end_tick)} s, {pace_text(speed)}."
    parts = []
    if scenario_description and waypoints is None:
        parts.append(f"{scenario_name}: {scenario_description}.")
    start = f"from t = {seconds(startup_ticks)} s" if startup_ticks else "from the first tick"
    note = own_lab_note(lab)
    if note is None:
        parts.append(f"The framework calls lab() every 1 ms {start}; what the lab prints follows on stdout "
                     "exactly as Tera Term shows it.")
    else:
        parts.append(f"The framework calls lab() every 1 ms {start}. {note}")
    if console:
        parts.append("Type list, get NAME or set NAME VALUE to see and change its watched variables.")
    parts.append("Scenario events are announced here as they happen (--quiet: no notes).")
    body = textwrap.fill(" ".join(parts), WIDTH, initial_indent="  ", subsequent_indent="  ")
    return f"{head}\n{body}\n"
