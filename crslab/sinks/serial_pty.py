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

from pathlib import Path

from crslab.host_tools.ports import HostPort, PortError, PtyPort
from crslab.sinks.sink import Sink


class PtyError(Exception):
    """The pseudo-terminal or its symlink could not be set up."""


class PortSink(Sink):
    """The board's serial output (SerialA) on a host port: a pseudo-terminal or a TCP connection.
    What the terminal types is read and discarded, as the board discards it."""

    def __init__(self, port: HostPort) -> None:
        self.port = port

    def attached(self) -> bool:
        """True while a terminal program has the port open."""
        return self.port.attached()

    def wait_attached(self, poll_s: float = 0.05) -> None:
        """Block until a terminal program opens the port (``--pty-wait``); Ctrl-C stops waiting."""
        import time

        while not self.attached():
            time.sleep(poll_s)  # a pseudo-terminal signals no event when its terminal end is opened

    def on_serial(self, tick: int, data: bytes) -> None:
        """Send the bytes that left the board to the terminal, if one is attached."""
        self.port.read()  # keystrokes from the terminal: the board ignores them
        self.port.write(data)

    def drain(self, timeout_s: float = 1.0) -> None:
        """Give an attached reader up to ``timeout_s`` to read what is buffered (at the end)."""
        import time

        if not self.attached():
            return
        end = time.monotonic() + timeout_s
        time.sleep(0.05)  # the kernel moves written bytes to the reader's side a moment later
        while time.monotonic() < end and self.port.unread() > 0:
            time.sleep(0.02)

    def close(self) -> None:
        """Give an attached terminal a moment to read the last bytes (:meth:`drain`), then close
        the port (and remove its symlink): the reader sees the port go away."""
        self.drain()
        self.port.close()


class PtySink(PortSink):
    """A serial sink that writes to a new pseudo-terminal (``path``), optionally linked at ``link``."""

    port: PtyPort

    def __init__(self, link: Path | None = None) -> None:
        try:
            super().__init__(PtyPort(link))
        except PortError as exc:
            named = link is not None and str(link) in str(exc)
            raise PtyError(f"--pty-link {exc}" if named else str(exc)) from None

    @property
    def path(self) -> str:
        """The terminal end's path (``/dev/pts/N``)."""
        return self.port.path

    @property
    def link(self) -> Path | None:
        """The stable symlink to it, if any."""
        return self.port.link

    @property
    def sent(self) -> int:
        return self.port.sent

    @property
    def dropped_unattached(self) -> int:
        return self.port.dropped_unattached

    @property
    def dropped_slow(self) -> int:
        return self.port.dropped_slow
