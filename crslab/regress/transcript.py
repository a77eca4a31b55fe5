"""Golden transcripts: the exact bytes a lab printed, after a small header, and the printed
lines with the simulated time each one was printed at.

A golden file written by ``crslab record``::

    # crslab transcript: the exact bytes the lab printed follow the '# ----' line
    # crslab: 0.1.0
    # lab: lab1.c
    # lab_sha256: 5f0c...
    # scenario: tour
    # scenario_sha256: 9a41...
    # end_s: 25.000
    # rest_motor_rad: 0 -0.42 0.24
    # startup_delay: yes
    # ----
    0.00 -24.06 13.75

A file without this header (say one ``crslab sim --transcript`` wrote) is a golden file too: all
of it is the transcript.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

MAGIC = b"# crslab transcript"
HEADER_END = b"# ----\n"
_LINE_END = re.compile(rb"\n\r|\r\n|\n|\r")


class GoldenError(ValueError):
    """A golden file that cannot be read; the message names the file."""


@dataclass(frozen=True)
class Line:
    """One printed line: its 1-based ``number``, its ``text`` (no line end) and the ``tick`` of the
    serial_printf call that printed its first byte (None when not known)."""

    number: int
    text: str
    tick: int | None = None

    @property
    def time(self) -> str:
        """The simulated time, as reports show it.

        >>> Line(3, "0.00", 4100).time
        't = 4.100 s'
        """
        return "t = ?" if self.tick is None else f"t = {self.tick / 1000:.3f} s"


@dataclass(frozen=True)
class Golden:
    """A golden file: its header fields and the transcript bytes."""

    path: Path
    header: dict[str, str] = field(default_factory=dict)
    body: bytes = b""


def sha256_of(data: bytes) -> str:
    """Short content hash used in headers (16 hex digits of SHA-256).

    >>> sha256_of(b"")
    'e3b0c44298fc1c14'
    """
    return hashlib.sha256(data).hexdigest()[:16]


def split_lines(data: bytes, calls: Sequence[tuple[int, bytes]] | None = None) -> list[Line]:
    r"""The lines of a transcript. Line ends are ``\n\r`` (the course's), ``\r\n``, ``\n`` or a lone
    ``\r``; text after the last line end is a line too. With ``calls`` (the (tick, bytes) of each
    serial_printf call, whose bytes make up ``data``) every line gets its tick.

    >>> [(l.number, l.text, l.tick) for l in split_lines(b"a 1\n\rb", [(4100, b"a 1\n\r"), (4600, b"b")])]
    [(1, 'a 1', 4100), (2, 'b', 4600)]
    """
    starts: list[int] = []
    ticks: list[int] = []
    if calls is not None:
        offset = 0
        for tick, chunk in calls:
            starts.append(offset)
            ticks.append(tick)
            offset += len(chunk)

    def tick_at(pos: int) -> int | None:
        if not starts:
            return None
        lo, hi = 0, len(starts) - 1
        while lo < hi:  # last call starting at or before pos
            mid = (lo + hi + 1) // 2
            if starts[mid] <= pos:
                lo = mid
            else:
                hi = mid - 1
        return ticks[lo]

    out = []
    pos = 0
    for m in _LINE_END.finditer(data):
        out.append(Line(len(out) + 1, data[pos:m.start()].decode("latin-1"), tick_at(pos)))
        pos = m.end()
    if pos < len(data):
        out.append(Line(len(out) + 1, data[pos:].decode("latin-1"), tick_at(pos)))
    return out


def make_header(fields: dict[str, str]) -> bytes:
    """The header block for ``fields`` (written in the given order)."""
    lines = [MAGIC + b": the exact bytes the lab printed follow the '# ----' line\n"]
    for key, value in fields.items():
        if "\n" in key or "\n" in value or ":" in key:
            raise ValueError(f"bad header field {key!r}: {value!r}")
        lines.append(f"# {key}: {value}\n".encode())
    return b"".join(lines) + HEADER_END


def write_golden(path: Path, fields: dict[str, str], transcript: bytes) -> None:
    """Write a golden file: the header, then the transcript bytes exactly."""
    path.write_bytes(make_header(fields) + transcript)


def read_golden(path: Path) -> Golden:
    """Read a golden file (with or without a crslab header).

    >>> import tempfile, os
    >>> d = tempfile.mkdtemp(); p = Path(d) / "g.txt"
    >>> write_golden(p, {"scenario": "tour"}, b"1.00\\n\\r")
    >>> g = read_golden(p); g.header, g.body
    ({'scenario': 'tour'}, b'1.00\\n\\r')
    """
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise GoldenError(f"{path}: no such golden file") from None
    except OSError as exc:
        raise GoldenError(f"{path}: cannot be read ({exc.strerror})") from None
    if not data.startswith(MAGIC):
        return Golden(path, {}, data)
    end = data.find(b"\n" + HEADER_END)
    if end < 0:
        raise GoldenError(f"{path}: the crslab header has no end line ('# ----')")
    header: dict[str, str] = {}
    for number, raw in enumerate(data[:end].split(b"\n")[1:], start=2):
        text = raw.decode("utf-8", "replace")
        key, sep, value = text[2:].partition(": ")
        if not text.startswith("# ") or not sep:
            raise GoldenError(f"{path}:{number}: header line must read '# key: value', got {text!r}")
        header[key.strip()] = value.strip()
    return Golden(path, header, data[end + 1 + len(HEADER_END):])
