"""A running lab as the windows into it see it between two chunks of ticks.

The live-variable console, MuJoCo's viewer and the waypoint tracking all act on a lab while it
runs, through this one interface (:class:`crslab.run.board_run.BoardRun` has it): read and write
its watched variables (``get``, ``set``), push the arm (``push``), and know the run's
configuration and current tick; the serial bridge exchanges bytes with the host ports
(``exchange``). Each of them that acts after every chunk of ticks is a :class:`LiveControl`, handed
to ``BoardRun.run(controls=...)``; one that needs short chunks is a :class:`PacedControl`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol, runtime_checkable

import numpy as np

if TYPE_CHECKING:
    from crslab.run.host_ports import PortExchange
    from crslab.worker.config import RunConfig


class RunningLab(Protocol):
    """A lab running in its worker, idle between two chunks of ticks."""

    @property
    def config(self) -> RunConfig:
        """The run's configuration: the lab's build (watched variables), the scenario, the options."""
        ...

    @property
    def tick(self) -> int:
        """The next tick to run (t = tick ms)."""
        ...

    def get(self, name: str) -> float | list[float]:
        """A watched variable's value (a list for an array)."""
        ...

    def set(self, name: str, value: float, index: int | None = None) -> None:
        """Write a watched variable, or one element of a watched array."""
        ...

    def push(self, body_forces: np.ndarray) -> None:
        """Apply a force and torque to each body (MuJoCo ``xfrc_applied``) until the next push."""
        ...

    def exchange(self, port: str, incoming: bytes) -> PortExchange:
        """What left the board on host port ``port`` (``SerialB``, ``SerialC``) since the last
        call; ``incoming`` goes to its receiver from the next tick on (as much as it takes now)."""
        ...


class LiveControl(Protocol):
    """Something that acts on the running lab after every chunk of ticks (typed commands, the
    viewer's mouse)."""

    def serve(self, lab: RunningLab) -> None:
        """Act on ``lab`` now (its worker is idle)."""
        ...


class RunDebugger(Protocol):
    """A debugger's say in a run (``crslab debug``, crslab/debug/): where chunks of ticks must end,
    and what it does there while the worker is idle (attach, ask for a stop in ``lab()``)."""

    def pause_tick(self) -> int | None:
        """The tick the run must stop before (a chunk ends there), or None."""
        ...

    def paused(self, lab: RunningLab, condition_held: bool) -> None:
        """The run stopped before ``lab.tick``: the tick :meth:`pause_tick` named, or
        (``condition_held``) the first tick where the lab's ``--break-when`` condition holds."""


@runtime_checkable
class PacedControl(LiveControl, Protocol):
    """A live control that must act more often than the default chunks allow (a host program on a
    serial port expects its answers within milliseconds)."""

    def chunk_ticks(self, speed: float | None) -> int | None:
        """The most ticks the next chunk may last at ``speed`` (None: as fast as possible); None
        when it has no need now."""
        ...
