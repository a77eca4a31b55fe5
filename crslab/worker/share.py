"""What one run may take of a board worker it shares with other runs: a server's run host
(crslab/serve/run_host.py) runs every page's lab as an instance of one worker, one chunk after
another, so no run may hold the worker long, whatever its lab does.

A run's chunk ends at the first tick after it used :attr:`Share.chunk_s` of the worker's CPU time
(``CRS_RUN_CUT``: the host runs the rest later); one call of its firmware (``lab()``,
``printing()``, a constructor) may cost :attr:`Share.call_instructions` WebAssembly instructions
(what the board walks for it, a ``writev``'s iovecs, included) and use :attr:`Share.call_s` of CPU
time: past either its run ends (the board could not keep its 1 ms tick either). CPU time, not wall
time: what a run takes is what it used, however busy the machine. The board's watchdog looks every
``CRS_WATCH_PERIOD_NS``, so it cuts a chunk within one period of its share and ends a call within
two of its limit (it first sees a call up to a period after it began). So a chunk holds the worker
for at most :func:`most_held_s` of CPU time: the longest any run delays another on its host.

``crslab sim`` gives its one run a worker of its own: none of this applies there (a lab slower
than real time is slower, as it would be on the bench).

>>> HOST_SHARE.chunk_s, HOST_SHARE.call_s, HOST_SHARE.call_instructions
(0.01, 0.02, 15000000)
>>> round(most_held_s(HOST_SHARE), 3)
0.045
>>> board_ms(HOST_SHARE.call_instructions)  # what that call would take the F28335
100.0
"""

from __future__ import annotations

from dataclasses import dataclass

from crslab.framework_facts import CPU_CYCLES_PER_TICK, TICKS_PER_S


@dataclass(frozen=True)
class Share:
    """What one run may take of a shared worker (see the module's text)."""

    chunk_s: float = 0.01
    """A chunk ends at the first tick after it used this much of the worker's CPU time (s)."""
    call_s: float = 0.02
    """One call of the firmware may use this much CPU time (s): more ends the run."""
    call_instructions: int = 15_000_000
    """One call of the firmware may cost this many WebAssembly instructions: more ends the run."""

    def options(self) -> dict[str, int]:
        """The board's fields for it (``crs_wasm_options``)."""
        return {"call_instructions": self.call_instructions, "call_ns": round(self.call_s * 1e9),
                "chunk_ns": round(self.chunk_s * 1e9)}


HOST_SHARE = Share()
"""A server's run hosts' (docs/serve.md, "A run's share of its host")."""


def watch_period_s() -> float:
    """How often the board's watchdog looks at the running call (s): a call is ended within this of
    its limit."""
    from crslab._bindings import constants

    return constants.CRS_WATCH_PERIOD_NS / 1e9


def most_held_s(share: Share) -> float:
    """The most CPU time one run's chunk holds a shared worker (s): its share and a period until the
    watchdog cuts it, then its last call (its limit and two periods)."""
    return share.chunk_s + share.call_s + 3 * watch_period_s()


def board_ms(instructions: int) -> float:
    """What ``instructions`` would take the F28335 (ms, one per cycle at 150 MHz), to 0.1 ms."""
    return round(instructions / CPU_CYCLES_PER_TICK * 1000 / TICKS_PER_S, 1)
