"""The course's lab templates the page starts from: one per framework generation, headed by the lab.

The files (``templates/gen_a.c``, ``templates/gen_b.c``) are written the way the course's Gen A
``CRSRobot`` and Gen B ``me446 starter`` files are: offsets, a counter that prints every 0.5 s
through ``printing()``, watched variables for the MATLAB tools, the four ``Simulink_PlotVar``.

>>> name, text = template("lab2", "B")
>>> name, text.splitlines()[0][:60]
('lab2.c', '/* Lab 2: PD and PID control, feedforward, trajectories: a s')
"""

from __future__ import annotations

from pathlib import Path

LABS = {
    "lab1": "Lab 1: kinematics, offsets and printing",
    "lab2": "Lab 2: PD and PID control, feedforward, trajectories",
    "lab3": "Lab 3: friction compensation and inverse dynamics",
    "lab4": "Lab 4: task-space PD and impedance control",
    "project": "Final project: waypoints with per-segment stiffness",
}
"""The labs of the course, as the page lists them."""
GENERATIONS = {"A": "gen_a.c", "B": "gen_b.c"}
FOLDER = Path(__file__).parent / "templates"


def template(lab: str, generation: str) -> tuple[str, str]:
    """The file name and text of ``lab``'s template for ``generation`` (``A`` or ``B``)."""
    if lab not in LABS:
        raise KeyError(f"no lab {lab!r}; choose one of {', '.join(LABS)}")
    if generation not in GENERATIONS:
        raise KeyError(f"no generation {generation!r}; choose A or B")
    text = (FOLDER / GENERATIONS[generation]).read_text()
    return f"{lab}.c", text.replace("@LAB@", LABS[lab], 1)
