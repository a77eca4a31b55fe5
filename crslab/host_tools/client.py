"""crslab's own host program for the board's serial ports, for users without MATLAB or Simulink
(``crslab serial``): it opens a port as they do (a serial device or pseudo-terminal at 115200
baud 8N1, or a TCP port of ``crslab sim --serial-tcp``) and speaks the same protocols
(:mod:`crslab.host_tools.serial_protocols`). It works against the real board's COM port too.
"""

from __future__ import annotations

import os
import select
import socket
import struct
import termios
import time
import tty
from pathlib import Path

from crslab.framework_facts import SERIAL_BAUD
from crslab.host_tools.serial_protocols import READ_REPLY, read_request, write_request

MATLAB_TIMEOUT_S = 10.0
"""How long the course's MATLAB scripts wait for a byte (MATLAB's default serial Timeout)."""


class LinkError(Exception):
    """The port cannot be opened, or the board did not answer as the protocol says."""


class SerialLink:
    """An open port: a serial device or pseudo-terminal (``path``), or a TCP connection
    (``tcp``: ``PORT`` or ``HOST:PORT``)."""

    def __init__(self, path: Path | None = None, tcp: str | None = None) -> None:
        self._sock: socket.socket | None = None
        self._fd = -1
        if tcp is not None:
            host, _, port = tcp.rpartition(":")
            try:
                self._sock = socket.create_connection((host or "127.0.0.1", int(port)), timeout=5.0)
            except (OSError, ValueError) as exc:
                why = getattr(exc, "strerror", None) or exc
                raise LinkError(f"cannot connect to TCP {tcp} ({why})") from None
            self._sock.setblocking(False)
            self.name = f"TCP {tcp}"
            return
        assert path is not None
        try:
            self._fd = os.open(path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        except OSError as exc:
            raise LinkError(f"{path}: cannot open the port ({exc.strerror})") from None
        try:
            tty.setraw(self._fd)  # 8 data bits, no parity, no translation
            attrs = termios.tcgetattr(self._fd)
            speed = getattr(termios, f"B{SERIAL_BAUD}")
            attrs[4] = attrs[5] = speed
            attrs[2] |= termios.CLOCAL | termios.CREAD
            attrs[2] &= ~(termios.CSTOPB | termios.PARENB)
            termios.tcsetattr(self._fd, termios.TCSANOW, attrs)
        except termios.error:
            pass  # not a terminal (a plain file, a fifo): raw bytes anyway
        self.name = str(path)

    def _fileno(self) -> int:
        return self._sock.fileno() if self._sock is not None else self._fd

    def _take(self, n: int) -> bytes:
        """Up to ``n`` bytes that have arrived (BlockingIOError: none after all); a port that went
        away or closed is a :class:`LinkError`."""
        try:
            chunk = self._sock.recv(n) if self._sock is not None else os.read(self._fd, n)
        except BlockingIOError:
            raise  # an OSError too, but only "nothing yet": the caller's to handle
        except OSError as exc:
            raise LinkError(f"{self.name}: the port went away ({exc.strerror or exc})") from None
        if not chunk:
            raise LinkError(f"{self.name}: the port closed (did the run end?)")
        return chunk

    def write(self, data: bytes) -> None:
        """Send every byte of ``data``."""
        view = memoryview(data)
        while view:
            select.select([], [self._fileno()], [], 5.0)
            try:
                n = self._sock.send(view) if self._sock is not None else os.write(self._fd, view)
            except BlockingIOError:
                continue
            except OSError as exc:
                raise LinkError(f"{self.name}: the port went away ({exc.strerror or exc})") from None
            view = view[n:]

    def read(self, n: int, timeout_s: float) -> bytes:
        """Up to ``n`` bytes, waiting at most ``timeout_s`` for them all (fewer on a timeout)."""
        out = b""
        end = time.monotonic() + timeout_s
        while len(out) < n:
            left = end - time.monotonic()
            if left <= 0 or not select.select([self._fileno()], [], [], left)[0]:
                break
            try:
                out += self._take(n - len(out))
            except BlockingIOError:
                continue
        return out

    def read_available(self) -> bytes:
        """What has arrived, without waiting."""
        out = b""
        while select.select([self._fileno()], [], [], 0)[0]:
            try:
                out += self._take(65536)
            except BlockingIOError:
                break
        return out

    def discard_input(self) -> None:
        """Drop what arrived and was not read (a stale reply)."""
        while select.select([self._fileno()], [], [], 0)[0]:
            try:
                self._take(65536)
            except (BlockingIOError, LinkError):  # nothing more, or a port that went away or closed
                return

    def close(self) -> None:
        """Close the port."""
        if self._sock is not None:
            self._sock.close()
            self._sock = None
        if self._fd >= 0:
            os.close(self._fd)
            self._fd = -1

    def __enter__(self) -> SerialLink:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def read_floats(link: SerialLink, address: int, count: int,
                timeout_s: float = MATLAB_TIMEOUT_S) -> list[float]:
    """Read ``count`` floats from ``address`` on, as ``ME446_serialread`` does: skip to the reply's
    ``*``, ignore its length byte, expect the code ``3``, then the floats little endian."""
    link.discard_input()
    link.write(read_request(address, count))
    while True:
        b = link.read(1, timeout_s)
        if not b:
            raise LinkError(f"{link.name}: no reply within {timeout_s:g} s (is crslab sim running with this "
                            "port, and SerialC's receiver not wedged?)")
        if b[0] == ord("*"):
            break
    head = link.read(2, timeout_s)
    if len(head) < 2 or head[1] != READ_REPLY:
        raise LinkError(f"{link.name}: the reply is not a read's (code {head[1:].hex() or 'missing'})")
    data = link.read(4 * count, timeout_s)
    if len(data) < 4 * count:
        raise LinkError(f"{link.name}: only {len(data) // 4} of {count} floats arrived within "
                        f"{timeout_s:g} s (the board's transmit ring holds about 500; it dropped the rest)")
    return list(struct.unpack(f"<{count}f", data))


def write_float(link: SerialLink, address: int, value: float) -> None:
    """Write ``value`` as a float at ``address``, as ``ME446_serialwrite`` does (no reply)."""
    link.write(write_request(address, value))
