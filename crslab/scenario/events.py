"""The kinds of scenario event. Each is a frozen dataclass with the tick it happens at (integer
ms) and a ``kind`` name used in TOML files; the worker applies it between ticks.

Times in scenario files are simulated seconds; they are converted once, here, to ticks.
"""

from __future__ import annotations

from dataclasses import dataclass


def seconds_to_tick(seconds: float) -> int:
    """Simulated seconds to the tick (ms) at which something happens, rounded to the nearest.

    >>> seconds_to_tick(4.1)
    4100
    """
    return int(round(seconds * 1000.0))


@dataclass(frozen=True)
class HandMove:
    """The hand takes the arm to ``target_dh_rad`` over ``duration_ticks`` and holds it there.

    ``target_dh_rad`` is None for the arm's true resting pose (known only when the run starts).
    """

    tick: int
    target_dh_rad: tuple[float, float, float] | None
    duration_ticks: int
    kind: str = "hand"


@dataclass(frozen=True)
class HandRelease:
    """The hand lets go of the arm."""

    tick: int
    kind: str = "release"


Event = HandMove | HandRelease
