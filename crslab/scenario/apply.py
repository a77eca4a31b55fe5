"""Apply a scenario event to the running worker, between ticks (in the worker process)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from crslab.scenario.events import Event, HandMove, HandRelease

if TYPE_CHECKING:
    from crslab.sim.worker import Worker


def apply_event(worker: Worker, event: Event) -> None:
    """Carry out ``event`` on the worker's plant, board or lab at the current tick."""
    sim = worker.sim
    hand = sim.hand
    if isinstance(event, HandMove):
        target = worker.rest_dh if event.target_dh_rad is None else event.target_dh_rad
        hand.active = 1
        hand.start_tick = sim.tick
        hand.duration_ticks = event.duration_ticks
        for j in range(3):
            hand.start_dh_rad[j] = float(worker.data.qpos[j])
            hand.target_dh_rad[j] = float(target[j])
    elif isinstance(event, HandRelease):
        hand.active = 0
        for j in range(3):
            hand.integral_rad_s[j] = 0.0
    else:  # pragma: no cover - the loader only makes known kinds
        raise TypeError(f"no way to apply {event!r}")
