"""A sink that keeps everything in memory: ``simulate()``, the regression commands and tests read it."""

from __future__ import annotations

import numpy as np

from crslab.sinks.sink import Sink


class MemorySink(Sink):
    """Keeps the serial calls with their ticks and the scope columns.

    >>> m = MemorySink()
    >>> m.on_serial(4100, b"1.00\\n\\r"); m.on_log({"tick": np.array([[0], [1]])})
    >>> m.transcript, m.log["tick"].ravel().tolist()
    (b'1.00\\n\\r', [0, 1])
    """

    def __init__(self) -> None:
        self.calls: list[tuple[int, bytes]] = []
        self.blocks: list[dict[str, np.ndarray]] = []

    def on_serial(self, tick: int, data: bytes) -> None:
        self.calls.append((tick, data))

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        self.blocks.append(columns)

    @property
    def transcript(self) -> bytes:
        """Every byte printed, in order."""
        return b"".join(d for _, d in self.calls)

    @property
    def log(self) -> dict[str, np.ndarray] | None:
        """All scope rows, one per tick (None when nothing was logged)."""
        if not self.blocks:
            return None
        return {k: np.concatenate([b[k] for b in self.blocks]) for k in self.blocks[0]}
