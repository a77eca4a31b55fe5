"""The server's side of the run hosts: a few processes (about one per core) that run every page's
lab (:mod:`crslab.serve.run_host`), started from the sessions' fork server when a page first
builds or runs (while its lab builds), each spoken to over one pipe on the server's event loop.

A session process hands the server a prepared run; :meth:`RunHosts.hand` gives it to the host with
the fewest runs, and from then on the page's commands for that run go to that host
(:meth:`RunHosts.command`), and the host's messages for the page come back tagged with the session's
id: the server only relays their bytes into the session's outbox. A host that ends unexpectedly
ends its runs (``crashed``, one line each); the next run starts a new one.
"""

from __future__ import annotations

import asyncio
import os
import socket
from collections.abc import Callable
from dataclasses import dataclass, field

from crslab.run.status import RunStatus
from crslab.serve import wire
from crslab.serve.run_host import serve_host

HOST_GONE = wire.ended(RunStatus.CRASHED, "crslab's run host ended unexpectedly")
"""What the page of each run of a run host that ended unexpectedly is told."""

Outbox = Callable[[bytes, bytes], None]
"""Where a session's page messages go: ``(tag, message)``."""


@dataclass
class Host:
    """One run host as the server sees it: its process, its pipe, the sessions it runs."""

    process: object
    writer: asyncio.StreamWriter
    runs: dict[str, Outbox] = field(default_factory=dict)
    pump: asyncio.Task | None = None


class RunHosts:
    """The server's run hosts (``count``, default one per core), started from ``context()``'s fork
    server."""

    def __init__(self, context: Callable[[], object], count: int | None = None) -> None:
        self.context = context
        self.count = max(1, count or os.cpu_count() or 1)
        self.hosts: list[Host] = []
        self.of: dict[str, Host] = {}
        """The host of each hosted session's run, by session id."""
        self._lock = asyncio.Lock()

    @property
    def running(self) -> int:
        """Runs the hosts run now."""
        return sum(len(h.runs) for h in self.hosts)

    async def warm(self) -> None:
        """Start every host now (a page opened: its first run will not wait for one)."""
        await self._host()
        while len(self.hosts) < self.count:
            async with self._lock:
                if len(self.hosts) < self.count:
                    self.hosts.append(await self._start())

    async def _host(self) -> Host:
        async with self._lock:  # one start at a time: never more hosts than count
            if len(self.hosts) < self.count:
                self.hosts.append(await self._start())
        return min(self.hosts, key=lambda h: len(h.runs))

    async def _start(self) -> Host:
        ctx = self.context()

        def start() -> tuple[object, socket.socket]:
            parent, child = ctx.Pipe(duplex=True)  # type: ignore[attr-defined]
            proc = ctx.Process(target=serve_host, args=(child,), name="crslab serve run host")  # type: ignore[attr-defined]
            proc.start()  # not daemonic: it forks its board worker
            child.close()
            sock = socket.socket(fileno=os.dup(parent.fileno()))
            parent.close()
            return proc, sock

        proc, sock = await asyncio.to_thread(start)
        reader, writer = await asyncio.open_connection(sock=sock)
        host = Host(proc, writer)
        host.pump = asyncio.create_task(self._pump(host, reader))
        return host

    async def _pump(self, host: Host, reader: asyncio.StreamReader) -> None:
        """The host's page messages into their sessions' outboxes, until it ends."""
        try:
            while True:
                key, tag, body = wire.unhost_frame(await wire.read_frame(reader))
                outbox = host.runs.get(key)
                if tag == wire.RUN_ENDED:
                    host.runs.pop(key, None)
                    if self.of.get(key) is host:
                        del self.of[key]
                if outbox is not None:
                    outbox(tag, body)
        except (asyncio.IncompleteReadError, ConnectionError):
            pass
        finally:
            if host in self.hosts:
                self.hosts.remove(host)
            for key, outbox in host.runs.items():
                if self.of.get(key) is host:
                    del self.of[key]
                outbox(wire.RUN_ENDED, HOST_GONE)
            host.runs.clear()
            host.writer.close()
            await asyncio.to_thread(_reap, host.process)

    @staticmethod
    def _write(host: Host, msg: tuple) -> None:
        host.writer.write(wire.pickled(msg))

    async def _send(self, host: Host, msg: tuple) -> None:
        self._write(host, msg)
        await host.writer.drain()

    async def hand(self, key: str, run: bytes, outbox: Outbox, pending: Callable[[], list[dict]]) -> None:
        """Give session ``key``'s prepared run (a pickled :class:`~crslab.serve.run_host.HostedRun`)
        to a host, then the page's commands that came while it was being prepared (``pending()``
        takes them); from then on :meth:`command` sends the page's commands there."""
        host = await self._host()
        host.runs[key] = outbox
        self.of[key] = host
        self._write(host, (wire.RUN, key, run))  # the run, then what came before it, in one go
        for msg in pending():
            self._write(host, (wire.PAGE, key, msg))
        await host.writer.drain()

    def hosts_run(self, key: str) -> bool:
        """Whether a host runs session ``key``'s run now."""
        return key in self.of

    async def command(self, key: str, msg: dict) -> None:
        """A page's command for its hosted run."""
        host = self.of.get(key)
        if host is not None:
            await self._send(host, (wire.PAGE, key, msg))

    async def forget(self, key: str) -> None:
        """The page went: its run (if any) ends now, unseen."""
        host = self.of.pop(key, None)
        if host is not None:
            host.runs.pop(key, None)
            try:
                await self._send(host, (wire.CLOSE, key))
            except ConnectionError:
                pass

    async def close(self) -> None:
        """End every host (their pipes close: each closes its runs and its worker)."""
        for host in list(self.hosts):
            host.writer.close()
            if host.pump is not None:
                await host.pump


def _reap(process: object) -> None:
    process.join(10.0)  # type: ignore[attr-defined]
    if process.is_alive():  # type: ignore[attr-defined]
        process.kill()  # type: ignore[attr-defined]
        process.join()  # type: ignore[attr-defined]
