"""``--pty``: the board's serial output on a pseudo-terminal, for a terminal program to attach to.

Point pyserial's miniterm, picocom or screen at the path crslab prints (or at the stable symlink
of ``--pty-link``), as Tera Term is pointed at the board's COM port. The terminal end is in raw
mode, so the bytes arrive exactly as the board sends them (``\\n\\r`` line ends included).

**Bytes sent while no terminal is attached are dropped**, as on a real serial line: the board's
UART sends them whether or not anyone listens, and Tera Term shows only what arrives after it
opened the port. (A pseudo-terminal would otherwise keep up to a few kB for the next reader;
crslab checks for a reader before each write and discards anything left unread when the
reader goes away.) A reader that is attached but does not keep up never slows the simulation:
writes never block, and what does not fit in the terminal's buffer is dropped and counted.
To see everything from the first tick on, start the run only once the terminal is attached
(:meth:`PtySink.wait_attached`, ``--pty-wait``), as one opens Tera Term before starting the board.
"""

from __future__ import annotations

import errno
import os
import select
import termios
import tty
from pathlib import Path

from crslab.os_support import open_pty
from crslab.sinks.sink import Sink


class PtyError(Exception):
    """The pseudo-terminal or its symlink could not be set up."""


class PtySink(Sink):
    """A serial sink that writes to a new pseudo-terminal (``path``), optionally linked at ``link``."""

    def __init__(self, link: Path | None = None) -> None:
        try:
            self._master, slave, self.path = open_pty()
        except OSError as exc:
            raise PtyError(f"cannot open a pseudo-terminal ({exc.strerror})") from None
        tty.setraw(slave)  # the reader gets the bytes as sent: no echo, no CR/LF translation
        os.close(slave)  # with no slave open, the master reports POLLHUP: nobody is reading
        os.set_blocking(self._master, False)
        self._poll = select.poll()
        self._poll.register(self._master, select.POLLIN | select.POLLHUP)
        self.link = None
        self.sent = 0
        self.dropped_unattached = 0
        self.dropped_slow = 0
        self._attached = False
        if link is not None:
            self._make_link(Path(link))

    def _make_link(self, link: Path) -> None:
        if link.exists() and not link.is_symlink():
            self.close()
            raise PtyError(f"--pty-link {link}: exists and is not a symlink; not replacing it")
        try:
            if link.is_symlink():
                link.unlink()
            link.symlink_to(self.path)
        except OSError as exc:
            self.close()
            raise PtyError(f"--pty-link {link}: cannot create the symlink ({exc.strerror})") from None
        self.link = link

    def attached(self) -> bool:
        """True while a terminal program has the port open (also drains what it typed)."""
        events = dict(self._poll.poll(0)).get(self._master, 0)
        if events & select.POLLIN:  # keystrokes from the terminal: the board would ignore them
            try:
                os.read(self._master, 4096)
            except OSError:
                pass
        now = not events & select.POLLHUP
        if self._attached and not now:
            self._discard_unread()
        self._attached = now
        return now

    def wait_attached(self, poll_s: float = 0.05) -> None:
        """Block until a terminal program opens the port (``--pty-wait``); Ctrl-C stops waiting."""
        import time

        while not self.attached():
            time.sleep(poll_s)  # a pseudo-terminal signals no event when its terminal end is opened

    def _discard_unread(self) -> None:
        """Drop what the last reader left unread, so a new reader starts fresh."""
        try:
            fd = os.open(self.path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        except OSError:
            return
        try:
            termios.tcflush(fd, termios.TCIFLUSH)
        finally:
            os.close(fd)

    def on_serial(self, tick: int, data: bytes) -> None:
        """Send one serial_printf call's bytes to the terminal, if one is attached."""
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

    def drain(self, timeout_s: float = 1.0) -> None:
        """Give an attached reader up to ``timeout_s`` to read what is buffered (at the end)."""
        import time

        if not self.attached():
            return
        end = time.monotonic() + timeout_s
        time.sleep(0.05)  # the kernel moves written bytes to the reader's side a moment later
        while time.monotonic() < end and self._unread() > 0:
            time.sleep(0.02)

    def _unread(self) -> int:
        import fcntl
        import struct

        try:
            fd = os.open(self.path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        except OSError:
            return 0
        try:
            buf = fcntl.ioctl(fd, termios.FIONREAD, b"\0\0\0\0")
            return struct.unpack("i", buf)[0]
        finally:
            os.close(fd)

    def close(self) -> None:
        """Give an attached terminal a moment to read the last bytes (:meth:`drain`), then remove
        the symlink and close the terminal (the reader sees the port go away)."""
        if self._master >= 0:
            self.drain()
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
