"""A sink that keeps everything in memory: ``simulate()``, the regression commands and tests read it."""

from __future__ import annotations

import numpy as np

from crslab.sinks.sink import Sink


class MemorySink(Sink):
    """Keeps the serial bytes with their ticks, the print marks and the scope columns.

    >>> m = MemorySink()
    >>> m.on_print(4100, 6); m.on_serial(4100, b"1.00\\n\\r"); m.on_log({"tick": np.array([[0], [1]])})
    >>> m.transcript, m.log["tick"].ravel().tolist()
    (b'1.00\\n\\r', [0, 1])
    """

    def __init__(self) -> None:
        self.sent: list[tuple[int, bytes]] = []
        self.prints: list[tuple[int, int]] = []
        self.blocks: list[dict[str, np.ndarray]] = []

    def on_serial(self, tick: int, data: bytes) -> None:
        self.sent.append((tick, data))

    def on_print(self, tick: int, chars: int) -> None:
        self.prints.append((tick, chars))

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        self.blocks.append(columns)

    @property
    def transcript(self) -> bytes:
        """Every byte printed, in order."""
        return b"".join(d for _, d in self.sent)

    @property
    def calls(self) -> list[tuple[int, bytes]]:
        r"""Each serial_printf call's tick and the bytes of it the board sent (what fit its transmit
        ring), cut from the transcript by the print marks' counts.

        >>> m = MemorySink()
        >>> m.on_print(4100, 4); m.on_print(4100, 5); m.on_print(4600, 3)
        >>> m.on_serial(4100, b"ab c"); m.on_serial(4101, b"12\n\r3"); m.on_serial(4600, b"4\n\r")
        >>> m.calls
        [(4100, b'ab c'), (4100, b'12\n\r3'), (4600, b'4\n\r')]
        """
        data, start, out = self.transcript, 0, []
        for tick, chars in self.prints:
            out.append((tick, data[start:start + chars]))
            start += chars
        return out

    @property
    def log(self) -> dict[str, np.ndarray] | None:
        """All scope rows, one per tick (None when nothing was logged)."""
        if not self.blocks:
            return None
        return {k: np.concatenate([b[k] for b in self.blocks]) for k in self.blocks[0]}
