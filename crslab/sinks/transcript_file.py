"""``--transcript FILE``: the exact bytes the board sent (lines end in ``\\n\\r``, as the course's
files print them), flushed after every chunk of ticks so a crash loses nothing."""

from __future__ import annotations

from pathlib import Path

from crslab.output_paths import with_parent
from crslab.sinks.sink import Sink


class TranscriptSink(Sink):
    """The exact serial bytes, in a file."""

    def __init__(self, path: Path) -> None:
        self.file = open(with_parent(path), "wb")  # noqa: SIM115 - closed in close()

    def on_serial(self, tick: int, data: bytes) -> None:
        self.file.write(data)

    def flush(self) -> None:
        """Write what has arrived to disk."""
        self.file.flush()

    def close(self) -> None:
        self.file.close()
