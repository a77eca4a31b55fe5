"""The board's serial output on stdout, as Tera Term shows it (one newline per line)."""

from __future__ import annotations

import sys
from typing import BinaryIO

from crslab.sinks.sink import Sink


def tera_term_view(data: bytes) -> bytes:
    r"""What Tera Term shows for serial bytes: ``\n\r`` (and a lone ``\r\n``) become one newline.

    >>> tera_term_view(b"1.00 2.00\n\r3\r\n")
    b'1.00 2.00\n3\n'
    """
    return data.replace(b"\n\r", b"\n").replace(b"\r\n", b"\n")


class StdoutSink(Sink):
    """The serial output on ``stream`` (default: stdout), a line end split across two calls included."""

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
