"""The serial ports a host program opens to talk to the simulated board: a pseudo-terminal
(what a COM port is to MATLAB, Tera Term or Octave) or a TCP listener on localhost (for a MATLAB
on Windows reaching crslab under WSL). Both live in the crslab process, never in the sandboxed
worker; the bridge (:mod:`crslab.live.bridge`) carries their bytes to and from the board
between chunks of ticks.

Like a real serial line, a port delivers only while someone is attached: bytes sent while no
program has the port open are dropped, and what a program left unread when it closed the port is
discarded. Writes never block the simulation: what does not fit because the reader is slow is
dropped and counted.

>>> import os
>>> port = PtyPort()
>>> port.attached()
False
>>> fd = os.open(port.path, os.O_RDWR | os.O_NOCTTY)     # a host program opens the port
>>> port.attached(), os.write(fd, b"*\\x09"), port.read()
(True, 2, b'*\\t')
>>> port.write(b"reply"); os.read(fd, 5)
b'reply'
>>> os.close(fd); port.close()
"""

from __future__ import annotations

import errno
import fcntl
import os
import select
import socket
import struct
import termios
import tty
from pathlib import Path

from crslab.os_support import open_pty

READ_CHUNK = 65536


class PortError(Exception):
    """A port could not be set up (no pseudo-terminal, a symlink in the way, a TCP port in use)."""


class PtyPort:
    """A new pseudo-terminal whose terminal end (``path``, or the stable symlink ``link``) a host
    program opens as its serial port."""

    def __init__(self, link: Path | None = None) -> None:
        try:
            self._master, slave, self.path = open_pty()
        except OSError as exc:
            raise PortError(f"cannot open a pseudo-terminal ({exc.strerror})") from None
        tty.setraw(slave)  # the host gets the bytes as sent: no echo, no CR/LF translation
        os.close(slave)  # with no terminal end open, the master reports POLLHUP: nobody attached
        os.set_blocking(self._master, False)
        self._poll = select.poll()
        self._poll.register(self._master, select.POLLIN | select.POLLHUP)
        self.link: Path | None = None
        self.sent = 0
        self.dropped_unattached = 0
        self.dropped_slow = 0
        self._attached = False
        if link is not None:
            self._make_link(Path(link))

    @property
    def name(self) -> str:
        """Where a host program opens it."""
        return str(self.link or self.path)

    def _make_link(self, link: Path) -> None:
        if link.exists() and not link.is_symlink():
            self.close()
            raise PortError(f"{link}: exists and is not a symlink; not replacing it")
        try:
            if link.is_symlink():
                link.unlink()
            link.symlink_to(self.path)
        except OSError as exc:
            self.close()
            raise PortError(f"{link}: cannot create the symlink ({exc.strerror})") from None
        self.link = link

    def _events(self) -> int:
        return dict(self._poll.poll(0)).get(self._master, 0)

    def attached(self) -> bool:
        """True while a program has the port open."""
        now = not self._events() & select.POLLHUP
        if self._attached and not now:
            self._discard_unread()
        self._attached = now
        return now

    def read(self) -> bytes:
        """What the attached program wrote since the last call (never blocks)."""
        out = b""
        while self._events() & select.POLLIN:
            try:
                chunk = os.read(self._master, READ_CHUNK)
            except (BlockingIOError, OSError):  # EIO: the program closed the port
                break
            if not chunk:
                break
            out += chunk
        return out

    def write(self, data: bytes) -> None:
        """Send ``data`` to the attached program (dropped when none is attached)."""
        if not self.attached():
            self.dropped_unattached += len(data)
            return
        try:
            n = os.write(self._master, data)
        except BlockingIOError:
            n = 0
        except OSError as exc:
            if exc.errno not in (errno.EIO, errno.EAGAIN):
                raise
            n = 0
        self.sent += n
        self.dropped_slow += len(data) - n

    def _terminal_end(self) -> int | None:
        try:
            return os.open(self.path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        except OSError:
            return None

    def _discard_unread(self) -> None:
        """Drop what the last program left unread, so the next one starts fresh."""
        fd = self._terminal_end()
        if fd is not None:
            try:
                termios.tcflush(fd, termios.TCIFLUSH)
            finally:
                os.close(fd)

    def unread(self) -> int:
        """Bytes written and not yet read by the attached program."""
        fd = self._terminal_end()
        if fd is None:
            return 0
        try:
            return struct.unpack("i", fcntl.ioctl(fd, termios.FIONREAD, b"\0\0\0\0"))[0]
        finally:
            os.close(fd)

    def close(self) -> None:
        """Remove the symlink and close the port (the program sees it go away)."""
        if self.link is not None:
            try:
                if self.link.is_symlink() and os.readlink(self.link) == self.path:
                    self.link.unlink()
            except OSError:
                pass
            self.link = None
        if self._master >= 0:
            os.close(self._master)
            self._master = -1


class TcpPort:
    """A TCP listener on ``host``:``port`` (localhost by default) for one program at a time; a new
    connection replaces the one before it."""

    def __init__(self, port: int, host: str = "127.0.0.1") -> None:
        try:
            self._server = socket.create_server((host, port))
        except OSError as exc:
            why = os.strerror(exc.errno) if exc.errno else str(exc)
            raise PortError(f"cannot listen on TCP {host}:{port} ({why})") from None
        self._server.setblocking(False)
        self.address = f"{host}:{self._server.getsockname()[1]}"
        self._client: socket.socket | None = None
        self.sent = 0
        self.dropped_unattached = 0
        self.dropped_slow = 0

    @property
    def name(self) -> str:
        """Where a host program connects."""
        return f"TCP {self.address}"

    def _accept(self) -> None:
        while True:
            try:
                conn, _ = self._server.accept()
            except (BlockingIOError, OSError):
                return
            self._drop_client()
            conn.setblocking(False)
            conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self._client = conn

    def _drop_client(self) -> None:
        if self._client is not None:
            self._client.close()
            self._client = None

    def attached(self) -> bool:
        """True while a program is connected."""
        self._accept()
        return self._client is not None

    def read(self) -> bytes:
        """What the connected program sent since the last call (never blocks)."""
        if not self.attached():
            return b""
        out = b""
        while self._client is not None:
            try:
                chunk = self._client.recv(READ_CHUNK)
            except BlockingIOError:
                break
            except OSError:
                self._drop_client()
                break
            if not chunk:  # the program closed the connection
                self._drop_client()
                break
            out += chunk
        return out

    def write(self, data: bytes) -> None:
        """Send ``data`` to the connected program (dropped when none is connected)."""
        if not self.attached() or self._client is None:
            self.dropped_unattached += len(data)
            return
        try:
            n = self._client.send(data)
        except BlockingIOError:
            n = 0
        except OSError:
            self._drop_client()
            n = 0
        self.sent += n
        self.dropped_slow += len(data) - n

    def unread(self) -> int:
        """Unknown for TCP: the program's own buffer holds what it has not read."""
        return 0

    def close(self) -> None:
        """Stop listening and close the connection."""
        self._drop_client()
        self._server.close()


HostPort = PtyPort | TcpPort
"""A port a host program talks through."""
