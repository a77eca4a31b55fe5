r"""How the board's serial bytes become lines: the one rule, for the golden compare, a run's
result, the autograder's excerpt and the rerun log alike.

``\n\r`` (the course's line end), ``\r\n``, ``\n`` and a lone ``\r`` each end a line; text after
the last line end is a line too. Bytes are Latin-1 (one character each, as Tera Term shows them).

>>> split(b"a 1\n\rb\r\nc\rd\n")
[(0, 'a 1'), (5, 'b'), (8, 'c'), (10, 'd')]
"""

from __future__ import annotations

import re

LINE_END = re.compile(rb"\n\r|\r\n|\n|\r")
_OTHER_HALF = {b"\n": b"\r", b"\r": b"\n"}


def split(data: bytes) -> list[tuple[int, str]]:
    """Each line of ``data``: the offset of its first byte and its text, without its line end."""
    out = []
    pos = 0
    for m in LINE_END.finditer(data):
        out.append((pos, data[pos:m.start()].decode("latin-1")))
        pos = m.end()
    if pos < len(data):
        out.append((pos, data[pos:].decode("latin-1")))
    return out


class SerialLines:
    r"""The same lines, cut as the bytes arrive, each with the tick that completed it (for a log
    that shows them as the run goes); a line end whose two bytes come from two serial_printf calls
    is one line end.

    >>> lines = SerialLines()
    >>> lines.feed(4100, b"1.00 2.00\n\r3.0")
    [(4100, '1.00 2.00')]
    >>> lines.feed(4101, b"0\n")
    [(4101, '3.00')]
    >>> lines.feed(4102, b"\rok\r"), lines.feed(4103, b"\nx\ry"), lines.finish()
    ([(4102, 'ok')], [(4103, 'x')], [(4103, 'y')])
    """

    def __init__(self) -> None:
        self._partial = b""
        self._other_half = b""  # the byte that would complete the last call's one-byte line end
        self._last_tick = 0

    def feed(self, tick: int, data: bytes) -> list[tuple[int, str]]:
        """The lines completed by one serial_printf call's bytes."""
        if not data:
            return []
        if self._other_half and data.startswith(self._other_half):
            data = data[1:]
        self._other_half = b""
        self._last_tick = tick
        text = self._partial + data
        out = []
        pos = 0
        for m in LINE_END.finditer(text):
            out.append((tick, text[pos:m.start()].decode("latin-1")))
            pos = m.end()
            if pos == len(text):
                self._other_half = _OTHER_HALF.get(m.group(0), b"")
        self._partial = text[pos:]
        return out

    def finish(self) -> list[tuple[int, str]]:
        """A last line that never got its line end (at the tick of its last bytes)."""
        rest, self._partial = self._partial, b""
        return [(self._last_tick, rest.decode("latin-1"))] if rest else []
