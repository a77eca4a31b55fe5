"""How long each chunk of ticks is, and when a run's next chunk is due on the wall clock: the one
pacer of every run (``crslab sim``'s and the page's in ``crslab serve``).

Where chunks begin and end never changes what the lab sees, so the transcript is the same at any
speed. A run's :class:`Chunks` say how long its chunks are: as fast as possible,
``fast_ticks``; at ``speed`` x real time, ``realtime_ticks`` simulated ms scaled by the speed, or
(``aligned``) as long as it takes to end at the run's own phase of every ``realtime_ticks`` ms of
the machine's clock (a server's runs wake one after another, not all at once). A
:class:`~crslab.run.running.PacedControl` (a host program on a serial port, a page that acts)
shortens chunks to what it asks; a debugger makes them :data:`DEBUG_SLICE_TICKS` and ends one at
the tick it names. After a chunk, the run is due again when the wall clock reaches the tick it
reached (:meth:`Pacer.due_s`): ``crslab sim`` sleeps until then (:meth:`Pacer.wait`), a server
runs every due run of a worker in one go (crslab/serve/run_host.py).

>>> pacer = Pacer(None)
>>> pacer.next_chunk(0, 25_000, controls=())
(20000, None)
>>> Pacer(2.0).next_chunk(4100, 25_000, controls=())
(4140, None)
>>> page = Pacer(1.0, chunks=PAGE_CHUNKS, phase=0.2, start_s=100.0)  # tick 0 due at 100 s
>>> page.next_chunk(0, 25_000, controls=())  # ends at 100.3 s: 0.2 of a 250 ms period
(300, None)
>>> page.next_chunk(300, 25_000, controls=()), page.due_s(300)
((550, None), 100.3)
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import NamedTuple

from crslab.framework_facts import TICKS_PER_S
from crslab.run.running import LiveControl, PacedControl, RunDebugger

REALTIME_SLICE_TICKS = 20
FAST_SLICE_TICKS = 20_000
DEBUG_SLICE_TICKS = 20
"""Chunks of a debugged run: what was printed up to 19 ticks before a stop in the debugger is on
the terminal (a chunk's serial bytes are taken when it ends)."""
BEHIND_S = 0.5
"""How far behind the wall clock a run may fall before it counts as not keeping up."""


class Chunks(NamedTuple):
    """How long a run's chunks are: ``realtime_ticks`` at real time (x speed), ``fast_ticks`` as
    fast as possible; ``aligned``: at real time each ends at the pacer's phase of every
    ``realtime_ticks`` ms of the machine's clock (the first takes half a period to a period and a
    half to get there, never a sliver)."""

    realtime_ticks: int
    fast_ticks: int
    aligned: bool = False


TERMINAL_CHUNKS = Chunks(REALTIME_SLICE_TICKS, FAST_SLICE_TICKS)
"""``crslab sim``'s: 20 ms at real time (the terminal shows each line within 20 ms of its time)."""
PAGE_CHUNKS = Chunks(250, 1000, aligned=True)
"""The page's (``crslab serve``): 250 ms at real time while it only watches (each chunk reaches
the page up to 250 ms ahead of its ticks, and the page shows each tick at its time: every chunk
costs the server a fixed share of a core, docs/serve.md's Capacity); 1000 ticks as fast as
possible (the page sees progress, and Stop acts, every 1000 ticks). While the page acts its
control asks for short chunks (crslab/serve/stream.py)."""


_PACED: dict[type, bool] = {}


def _paced(control: LiveControl) -> bool:
    """Whether ``control`` is a :class:`~crslab.run.running.PacedControl` (asked once per class:
    a protocol's ``isinstance`` inspects the class every time)."""
    paced = _PACED.get(type(control))
    if paced is None:
        paced = _PACED[type(control)] = isinstance(control, PacedControl)
    return paced


class Waited(NamedTuple):
    """What :meth:`Pacer.wait` did: ``slept`` until due; ``behind``, the rate the run achieved,
    the first time it fell behind (else None)."""

    slept: bool
    behind: float | None


class Pacer:
    """One run's pacing at ``speed`` x real time (None: as fast as possible), from ``tick0``, due
    at ``start_s`` on the machine's monotonic clock (default: now), in chunks of ``chunks``
    (aligned ones at ``phase``, a fraction of their period)."""

    def __init__(self, speed: float | None, tick0: int = 0, debugger: RunDebugger | None = None, *,
                 chunks: Chunks = TERMINAL_CHUNKS, phase: float = 0.0, start_s: float | None = None) -> None:
        self.speed = speed
        self.debugger = debugger
        self.chunks = chunks
        self.phase = phase
        self.wall0 = time.monotonic() if start_s is None else start_s
        self.tick0 = tick0
        self._wall, self._tick = self.wall0, tick0  # where pacing counts from
        self._warned = False

    def elapsed_s(self) -> float:
        """Wall-clock seconds since the run started."""
        return time.monotonic() - self.wall0

    def due_s(self, tick: int) -> float:
        """When ``tick`` is due on the machine's monotonic clock (as fast as possible: now)."""
        if self.speed is None:
            return time.monotonic()
        return self._wall + (tick - self._tick) / TICKS_PER_S / self.speed

    def set_speed(self, speed: float | None, tick: int) -> None:
        """Go on at ``speed`` from ``tick``, due now."""
        self.speed = speed
        self.restart(tick)

    def restart(self, tick: int, at_s: float | None = None) -> None:
        """Pace from ``tick``, due now or at ``at_s`` on the monotonic clock (time the run was held
        is not made up for)."""
        self._wall, self._tick = time.monotonic() if at_s is None else at_s, tick

    def _step(self, tick: int) -> int:
        chunks = self.chunks
        if self.speed is None:
            return chunks.fast_ticks
        if not chunks.aligned:
            return max(1, int(chunks.realtime_ticks * self.speed))
        period_s = chunks.realtime_ticks / TICKS_PER_S
        ahead_s = (self.phase * period_s - self.due_s(tick)) % period_s
        if ahead_s < period_s / 2:  # the first chunk takes half a period or more, never a sliver
            ahead_s += period_s
        return max(1, min(chunks.fast_ticks, round(ahead_s * TICKS_PER_S * self.speed)))

    def next_chunk(self, tick: int, end_tick: int, controls: Sequence[LiveControl]) -> tuple[int, int | None]:
        """Where the chunk from ``tick`` ends, and the tick the debugger asks to stop before (None)."""
        step = min([self._step(tick)] + [t for c in controls if _paced(c)
                                         and (t := c.chunk_ticks(self.speed)) is not None])
        target = min(end_tick, tick + max(1, step))
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
        lag = time.monotonic() - self.due_s(tick)
        if lag < 0:
            time.sleep(-lag)
            return Waited(True, None)
        if lag > BEHIND_S and self.debugger is not None:
            self.restart(tick)
        elif lag > BEHIND_S and not self._warned:
            self._warned = True
            return Waited(False, (tick - self.tick0) / TICKS_PER_S / self.elapsed_s())
        return Waited(False, None)
