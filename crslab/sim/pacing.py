"""How long each chunk of ticks is, and how a run keeps to the wall clock between chunks.

Where chunks begin and end never changes what the lab sees, so the transcript is the same at any
speed: as fast as possible, a chunk is :data:`FAST_SLICE_TICKS`; at ``speed`` x real time it is
:data:`REALTIME_SLICE_TICKS` simulated ms scaled by the speed, then the run waits until the wall
clock is due for the tick it reached. A :class:`~crslab.sim.running.PacedControl` (a host program
on a serial port) shortens chunks to what it asks; a debugger makes them
:data:`DEBUG_SLICE_TICKS` and ends one at the tick it names.

>>> pacer = Pacer(None)
>>> pacer.next_chunk(0, 25_000, controls=())
(20000, None)
>>> Pacer(2.0).next_chunk(4100, 25_000, controls=())
(4140, None)
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import NamedTuple

from crslab.sim.running import LiveControl, PacedControl, RunDebugger

REALTIME_SLICE_TICKS = 20
FAST_SLICE_TICKS = 20_000
DEBUG_SLICE_TICKS = 20
"""Chunks of a debugged run: what was printed up to 19 ticks before a stop in the debugger is on
the terminal (a chunk's serial bytes are taken when it ends)."""
BEHIND_S = 0.5
"""How far behind the wall clock a run may fall before it counts as not keeping up."""


class Waited(NamedTuple):
    """What :meth:`Pacer.wait` did: ``slept`` until due; ``behind``, the rate the run achieved,
    the first time it fell behind (else None)."""

    slept: bool
    behind: float | None


class Pacer:
    """One run's pacing at ``speed`` x real time (None: as fast as possible), from ``tick0``."""

    def __init__(self, speed: float | None, tick0: int = 0, debugger: RunDebugger | None = None) -> None:
        self.speed = speed
        self.debugger = debugger
        self.wall0 = time.monotonic()
        self.tick0 = tick0
        self._wall, self._tick = self.wall0, tick0  # where pacing counts from
        self._warned = False

    def elapsed_s(self) -> float:
        """Wall-clock seconds since the run started."""
        return time.monotonic() - self.wall0

    def next_chunk(self, tick: int, end_tick: int, controls: Sequence[LiveControl]) -> tuple[int, int | None]:
        """Where the chunk from ``tick`` ends, and the tick the debugger asks to stop before (None)."""
        step = FAST_SLICE_TICKS if self.speed is None else max(1, int(REALTIME_SLICE_TICKS * self.speed))
        step = min([step] + [t for c in controls if isinstance(c, PacedControl)
                             and (t := c.chunk_ticks(self.speed)) is not None])
        target = min(end_tick, tick + step)
        pause = self.debugger.pause_tick() if self.debugger is not None else None
        if self.debugger is not None:
            target = min(target, tick + DEBUG_SLICE_TICKS)
            if pause is not None and pause > tick:
                target = min(target, pause)
        return target, pause

    def wait(self, tick: int) -> Waited:
        """Wait until the wall clock is due for ``tick``. Behind it, a debugged run paces from now
        on (the debugger held the lab: that time is not made up for); another says so once."""
        if self.speed is None:
            return Waited(False, None)
        lag = time.monotonic() - (self._wall + (tick - self._tick) / 1000.0 / self.speed)
        if lag < 0:
            time.sleep(-lag)
            return Waited(True, None)
        if lag > BEHIND_S and self.debugger is not None:
            self._wall, self._tick = time.monotonic(), tick
        elif lag > BEHIND_S and not self._warned:
            self._warned = True
            return Waited(False, (tick - self.tick0) / 1000.0 / self.elapsed_s())
        return Waited(False, None)
