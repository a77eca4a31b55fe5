"""What one run may take of a board worker it shares with other runs: a server's run host
(crslab/serve/run_host.py) runs every page's lab as an instance of one worker, one chunk after
another, so no run may hold the worker long, whatever its lab does.

A run's chunk ends at the first tick after :attr:`Share.chunk_s` of it (``CRS_RUN_CUT``: the host
runs the rest later); one call of its firmware (``lab()``, ``printing()``, a constructor) may cost
:attr:`Share.call_instructions` WebAssembly instructions (what the board walks for it, a
``writev``'s iovecs, included) and run :attr:`Share.call_s` of the worker's time: past either its
run ends (the board could not keep its 1 ms tick either). The watchdog ends a call within
``CRS_WATCH_PERIOD_NS`` of its limit. So a chunk holds the worker at most
:func:`most_held_s`: the longest any run delays another on its host.

``crslab sim`` gives its one run a worker of its own: none of this applies there (a lab slower
than real time is slower, as it would be on the bench).

>>> HOST_SHARE.chunk_s, HOST_SHARE.call_s, HOST_SHARE.call_instructions
(0.02, 0.02, 5000000)
>>> round(most_held_s(HOST_SHARE), 3)
0.05
>>> board_ms(HOST_SHARE.call_instructions)  # what that call would take the F28335
33.3
"""

from __future__ import annotations

from dataclasses import dataclass

from crslab.framework_facts import CPU_CYCLES_PER_TICK, TICKS_PER_S


@dataclass(frozen=True)
class Share:
    """What one run may take of a shared worker (see the module's text)."""

    chunk_s: float = 0.02
    """A chunk ends at the first tick after this much of the worker's time (s)."""
    call_s: float = 0.02
    """One call of the firmware may run this long (s): longer ends the run."""
    call_instructions: int = 5_000_000
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
    from crslab.worker.board_ffi import board_constants

    return board_constants().CRS_WATCH_PERIOD_NS / 1e9


def most_held_s(share: Share) -> float:
    """The longest one run's chunk holds a shared worker (s): its share, then its last call (at most
    ``call_s``, ended within the watchdog's period)."""
    return share.chunk_s + share.call_s + watch_period_s()


def board_ms(instructions: int) -> float:
    """What ``instructions`` would take the F28335 (ms, one per cycle at 150 MHz), to 0.1 ms."""
    return round(instructions / CPU_CYCLES_PER_TICK * 1000 / TICKS_PER_S, 1)
