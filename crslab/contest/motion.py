"""When a contest run's motion begins and ends, from the peg tip's path (one row per logged tick).

A TA starts the clock when the arm first moves and stops watching once it has come to rest after
its last task. crslab does the same with two numbers: the **first motion** is the first row whose
tip is :data:`MOTION_M` from where it was on the log's first row; the **motion has ended** once the
tip has stayed within :data:`STILL_M` of where it is now for :data:`STILL_S` (a press held for its
designed 2 s, a pause over the hole, stay well inside that), counted from after the first motion. A lab that
never moves is given :data:`NO_MOTION_S` after its first ``lab()`` call; no run lasts longer than
:data:`LONGEST_S` unless ``--duration`` says so.

>>> t = np.arange(0, 15001) / 1000.0                     # 15 s at 1 kHz
>>> tip = np.zeros((len(t), 3)); tip[:, 0] = np.clip(t - 2.0, 0.0, 1.0) * 0.1   # moves 2-3 s
>>> first_motion(t, tip)                     # past 5 mm along x from t = 2.051 s
2.051
>>> still_since(t, tip, first_s=2.051)       # within 2 mm of its end from t = 2.981 s
2.981
>>> still_since(t[:12000], tip[:12000], first_s=2.051) is None   # only 9 s still by t = 12 s
True
"""

from __future__ import annotations

import numpy as np

MOTION_M = 0.005
"""The first motion: the peg's tip this far (m) from where it was on the log's first row."""
STILL_M = 0.002
"""Still: the tip within this distance (m) of where it came to rest (a held press sways less than
that; the joints' static friction holds a stopped arm to a fraction of a millimetre)."""
STILL_S = 10.0
"""How long (s) the tip must stay still for the motion to have ended: five times the longest hold
the course's rules ask for (the egg's 2 s; the hole's is a moment), so that a lab's pause between
two tasks, or a press held longer than designed, does not end its run."""
NO_MOTION_S = 15.0
"""How long (s) after its first ``lab()`` call a lab that never moves the arm is given."""
LONGEST_S = 60.0
"""The longest contest run (simulated s, the 4.1 s start-up included) unless ``--duration``: twice
the 30 s crslab used to give every run, three times crslab's own starter's 21 s."""


def first_motion(t: np.ndarray, tip: np.ndarray) -> float | None:
    """When the tip is first :data:`MOTION_M` from where it was on the first row (s); None if never."""
    if len(tip) == 0:
        return None
    moved = np.linalg.norm(tip - tip[0], axis=1) > MOTION_M
    return float(t[np.argmax(moved)]) if moved.any() else None


def still_since(t: np.ndarray, tip: np.ndarray, first_s: float | None) -> float | None:
    """When the tip came to rest for good: the earliest time from which every row is within
    :data:`STILL_M` of the last row, if that lasted at least :data:`STILL_S` and began after the
    first motion (``first_s``); None otherwise (still moving, or never moved)."""
    if first_s is None or len(tip) == 0:
        return None
    far = np.linalg.norm(tip - tip[-1], axis=1) > STILL_M
    moving = np.flatnonzero(far)
    k = int(moving[-1]) + 1 if len(moving) else 0
    if k >= len(t):
        return None
    since = float(t[k])
    if since < first_s or t[-1] - since < STILL_S - 1e-9:
        return None
    return since
