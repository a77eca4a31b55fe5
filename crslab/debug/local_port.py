"""A TCP port on localhost only, relayed to gdbserver's standard input and output.

gdbserver listens on every network interface whatever host it is given (its sockets bind the
wildcard address), and whoever reaches its port controls the lab's process, with the user's
permissions. So ``crslab debug --gdbserver PORT`` runs gdbserver on its standard streams
(``gdbserver --attach -``) and listens itself, on the loopback addresses only (127.0.0.1, and
::1 where the machine has it): one connection, relayed byte for byte both ways.

>>> with LocalPort(0) as port:
...     port.port > 0, port.addresses[0] == ("127.0.0.1", port.port)
(True, True)
"""

from __future__ import annotations

import contextlib
import os
import selectors
import socket
import threading
from typing import IO


class PortError(OSError):
    """The port cannot be listened on; the message says why in one line."""


class LocalPort:
    """Listen on ``port`` of the loopback addresses (0: a free one, :attr:`port` says which)."""

    def __init__(self, port: int) -> None:
        self._sockets: list[socket.socket] = []
        self.addresses: list[tuple[str, int]] = []
        try:
            first = self._listen(socket.AF_INET, "127.0.0.1", port)
        except OSError as exc:
            raise PortError(f"localhost port {port} cannot be listened on ({exc.strerror})") from None
        self.port = first.getsockname()[1]
        with contextlib.suppress(OSError):  # a machine without IPv6 serves 127.0.0.1 alone
            self._listen(socket.AF_INET6, "::1", self.port)
        self._threads: list[threading.Thread] = []
        self._wake_read, self._wake_write = os.pipe()  # close() wakes a relay still waiting to accept

    def _listen(self, family: int, host: str, port: int) -> socket.socket:
        s = socket.socket(family, socket.SOCK_STREAM)
        try:
            s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            if family == socket.AF_INET6:
                s.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_V6ONLY, 1)
            s.bind((host, port))
            s.listen(1)
        except OSError:
            s.close()
            raise
        self._sockets.append(s)
        self.addresses.append((host, s.getsockname()[1]))
        return s

    def __enter__(self) -> LocalPort:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def relay(self, to_stdin: IO[bytes], from_stdout: IO[bytes]) -> None:
        """In the background: accept one connection and relay it to a process's standard input
        (``to_stdin``) and from its standard output (``from_stdout``) until either side ends."""
        t = threading.Thread(target=self._serve, args=(to_stdin, from_stdout), daemon=True)
        t.start()
        self._threads.append(t)

    def _serve(self, to_stdin: IO[bytes], from_stdout: IO[bytes]) -> None:
        with selectors.DefaultSelector() as sel:
            for s in self._sockets:
                sel.register(s, selectors.EVENT_READ)
            sel.register(self._wake_read, selectors.EVENT_READ)
            ready = sel.select()
            listening = [key.fileobj for key, _ in ready if key.fileobj is not self._wake_read]
            try:
                if not listening:
                    raise OSError("closed before anyone connected")
                conn, _ = listening[0].accept()  # type: ignore[union-attr]
            except OSError:
                with contextlib.suppress(OSError):
                    to_stdin.close()
                return
            finally:
                for s in self._sockets:
                    s.close()
        conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        back = threading.Thread(target=self._pump_back, args=(from_stdout, conn), daemon=True)
        back.start()
        try:
            while True:
                data = conn.recv(65536)
                if not data:
                    break
                to_stdin.write(data)
                to_stdin.flush()
        except OSError:
            pass
        finally:
            with contextlib.suppress(OSError):
                to_stdin.close()  # gdbserver --once: the session is over, it detaches and ends
        back.join()
        conn.close()

    @staticmethod
    def _pump_back(from_stdout: IO[bytes], conn: socket.socket) -> None:
        fd = from_stdout.fileno()
        try:
            while True:
                data = os.read(fd, 65536)
                if not data:
                    break
                conn.sendall(data)
        except OSError:
            pass
        with contextlib.suppress(OSError):
            conn.shutdown(socket.SHUT_RDWR)

    def close(self) -> None:
        """Stop listening (a relay in progress ends with either side)."""
        if self._wake_write >= 0:
            os.write(self._wake_write, b"x")
            for t in self._threads:
                t.join(5.0)
            os.close(self._wake_write)
            os.close(self._wake_read)
            self._wake_write = -1
        for s in self._sockets:
            with contextlib.suppress(OSError):
                s.close()
