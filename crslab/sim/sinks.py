"""Where a run's output goes: each sink takes serial bytes (with their tick) and scope rows.

The transcript file holds the exact bytes the board sent (lines end in ``\\n\\r``, as the
course's files print them); stdout shows them as Tera Term does (one newline per line).
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import BinaryIO

import numpy as np


class Sink:
    """Base sink: override what you need."""

    def on_serial(self, tick: int, data: bytes) -> None:
        """Bytes of one serial_printf call made during ``tick``."""

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        """Scope rows (one per tick) since the last call."""

    def close(self) -> None:
        """Flush and release; called once, also after a crash."""


def tera_term_view(data: bytes) -> bytes:
    r"""What Tera Term shows for serial bytes: ``\n\r`` (and a lone ``\r\n``) become one newline.

    >>> tera_term_view(b"1.00 2.00\n\r3\r\n")
    b'1.00 2.00\n3\n'
    """
    return data.replace(b"\n\r", b"\n").replace(b"\r\n", b"\n")


class StdoutSink(Sink):
    """The board's serial output on stdout, as Tera Term shows it."""

    def __init__(self, stream: BinaryIO | None = None) -> None:
        self.stream = stream if stream is not None else sys.stdout.buffer
        self._pending_cr = False

    def on_serial(self, tick: int, data: bytes) -> None:
        if self._pending_cr and data.startswith(b"\r"):
            data = data[1:]
        self._pending_cr = data.endswith(b"\n")
        self.stream.write(tera_term_view(data))

    def flush(self) -> None:
        """Push what was written to the terminal."""
        try:
            self.stream.flush()
        except BrokenPipeError:
            pass

    def close(self) -> None:
        self.flush()


class TranscriptSink(Sink):
    """The exact bytes, in a file, flushed after every chunk so a crash loses nothing."""

    def __init__(self, path: Path) -> None:
        self.file = open(path, "wb")  # noqa: SIM115 - closed in close()

    def on_serial(self, tick: int, data: bytes) -> None:
        self.file.write(data)

    def flush(self) -> None:
        """Write what has arrived to disk."""
        self.file.flush()

    def close(self) -> None:
        self.file.close()


class MemorySink(Sink):
    """Keeps everything: the serial calls with their ticks and the scope columns."""

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
