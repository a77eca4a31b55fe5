"""The server's side of the page sessions: one process each, the limits, and what the admin sees.

A session process is started from a fork server that imported crslab once
(:func:`session_context`), with a pipe to the server and a private folder; it builds and prepares
the page's runs, which the run hosts (:mod:`crslab.serve.run_hosts`) run. The server keeps, per
session, who owns it, when it started and what it runs (from the tags of the messages it relays,
:mod:`crslab.serve.page_process`), and enforces the per-user limits before it hands a message
on: one build, run or check at a time, compiles per minute, and the number of sessions at once
(the server's and each user's).
"""

from __future__ import annotations

import multiprocessing as mp
import os
import secrets
import shutil
import socket
import tempfile
import threading
import time
from dataclasses import dataclass, field
from multiprocessing.connection import Connection
from pathlib import Path

from crslab import os_support
from crslab.serve.auth import RateLimit
from crslab.serve.page_process import SessionLimits, serve_session
from crslab.serve.run_hosts import RunHosts

PRELOAD = [
    "crslab.serve.page_process",
    "crslab.serve.run_host",
    "crslab.worker.main",
    "crslab.sandbox.run_sandbox",
    "crslab.executors.warmup",
    "crslab.scopes.arm3d",
    "crslab.regress.runner",
]
"""What the fork server imports once (MuJoCo, numpy, the board's cffi, the compiler's identity),
so that a session process starts in milliseconds."""


def session_context() -> mp.context.BaseContext:
    """The fork server sessions start from (started now, so the first page does not wait)."""
    ctx = os_support.fork_server(PRELOAD)
    from multiprocessing import forkserver

    forkserver.ensure_running()
    return ctx


def run_phase(n: int) -> float:
    """Where in the pacing period the ``n``-th run's chunks end (a fraction of it): the golden
    ratio's multiples, so however many runs go at once their wake-ups lie evenly over the period
    (runs started together, or 50 ms apart, would otherwise share a handful of instants and each
    wait behind the others).

    >>> [round(run_phase(n), 3) for n in range(5)]
    [0.0, 0.618, 0.236, 0.854, 0.472]
    """
    return (n * 0.6180339887498949) % 1.0


@dataclass(frozen=True)
class UserLimits:
    """What one user may do: compiles (builds, runs, checks) per minute; one build, run or check
    at a time always, across all their pages."""

    compiles_per_minute: int = 6
    max_sessions: int = 200
    """Sessions on this server at once, all users together (``--max-sessions``)."""
    max_sessions_per_user: int = 2
    """Sessions of one user at once (``--max-sessions-per-user``): no one takes every session."""


class LimitError(Exception):
    """What the server refuses for a limit: one line for the page."""


@dataclass
class PageSession:
    """One page's session as the server sees it."""

    id: str
    user: str
    process: mp.process.BaseProcess
    conn: Connection
    folder: Path
    started_wall: float = field(default_factory=time.time)
    running: str | None = None
    """What runs now (``run`` or ``check``), None when idle."""
    scenario: str = ""
    runs: int = 0
    pending: list[dict] = field(default_factory=list)
    """The page's commands (stop, speed, ...) that came while its run was being prepared: handed
    to the run's host after the run."""

    def take_socket(self) -> socket.socket:
        """The server's end of the pipe as a socket (for asyncio), no longer as a Connection."""
        sock = socket.socket(fileno=os.dup(self.conn.fileno()))
        self.conn.close()
        return sock

    def describe(self) -> dict:
        """A row of the admin page."""
        return {
            "id": self.id[:8],
            "user": self.user,
            "since": time.strftime("%H:%M:%S", time.localtime(self.started_wall)),
            "state": self.running or "idle",
            "scenario": self.scenario,
            "runs": self.runs,
        }


class Sessions:
    """Every session of this server, with the users' limits."""

    def __init__(self, limits: UserLimits, run_limits: SessionLimits, run_hosts: int | None = None) -> None:
        self.limits = limits
        self.run_limits = run_limits
        self.by_id: dict[str, PageSession] = {}
        """Every session by id: changed only under ``_lock`` (sessions start and end in threads
        while the event loop reads it): read a snapshot, :meth:`all`."""
        self._lock = threading.Lock()
        self._starting: dict[str, int] = {}
        """Sessions whose process is starting, by user: their places are kept."""
        self._runs = 0
        self._compiles: dict[str, RateLimit] = {}
        self._ctx: mp.context.BaseContext | None = None
        self._ctx_lock = threading.Lock()
        self.hosts = RunHosts(self.context, run_hosts)
        """The run hosts: every page's run is an instance of one of their workers."""

    def context(self) -> mp.context.BaseContext:
        """The fork server sessions and run hosts start from (started at the first call)."""
        with self._ctx_lock:
            if self._ctx is None:
                self._ctx = session_context()
            return self._ctx

    def all(self) -> list[PageSession]:
        """The sessions now (a copy)."""
        with self._lock:
            return list(self.by_id.values())

    def start(self, user: str) -> PageSession:
        """A new session process for ``user`` (blocking: call it from a thread)."""
        with self._lock:
            if len(self.by_id) + sum(self._starting.values()) >= self.limits.max_sessions:
                raise LimitError(
                    f"this server is full ({self.limits.max_sessions} sessions at once); try again later"
                )
            mine = sum(s.user == user for s in self.by_id.values()) + self._starting.get(user, 0)
            if mine >= self.limits.max_sessions_per_user:
                raise LimitError(
                    f"you have {mine} pages open on this server, as many as one user may "
                    f"({self.limits.max_sessions_per_user}): close one to open this one"
                )
            self._starting[user] = self._starting.get(user, 0) + 1  # its place is kept while it starts
            self.context()
        session = None
        try:
            session = self._start(user)
        finally:
            with self._lock:  # its kept place becomes the session's (or is given back) at once
                self._starting[user] -= 1
                if not self._starting[user]:
                    del self._starting[user]
                if session is not None:
                    self.by_id[session.id] = session
        return session

    def _start(self, user: str) -> PageSession:
        folder = Path(tempfile.mkdtemp(prefix="crslab-serve-"))
        parent, child = self._ctx.Pipe(duplex=True)
        proc = self._ctx.Process(
            target=serve_session,
            args=(child, str(folder), self.run_limits),
            name=f"crslab serve session of {user}",
        )  # not daemonic: it forks the lab's worker
        proc.start()
        child.close()
        return PageSession(secrets.token_urlsafe(18), user, proc, parent, folder)

    def close(self, session: PageSession) -> None:
        """End a session: its process (and so its run) and its folder (blocking)."""
        with self._lock:
            self.by_id.pop(session.id, None)
        session.conn.close()  # (already closed when the relay took it): the session sees its pipe close
        # and is told to end now, not after the build or run it is in: its SIGTERM handler unwinds
        # it, so the compiler's process group and the run's worker end with it
        session.process.terminate()
        session.process.join(3.0)
        if session.process.is_alive():
            session.process.kill()
            session.process.join()
        shutil.rmtree(session.folder, ignore_errors=True)

    def admit(self, session: PageSession, msg: dict, now: float) -> None:
        """Check a page's message against the limits (raises :class:`LimitError`), and note a run."""
        kind = msg["type"]
        if kind not in ("build", "run", "check"):
            return
        if session.running is not None:
            raise LimitError(f"{kind}: a {session.running} is going on; stop it first")
        other = next((s for s in self.all() if s.user == session.user and s.running), None)
        if other is not None:  # builds too: a user's compilers run one at a time
            raise LimitError(
                f"{kind}: you have a {other.running} going on in another page; "
                "one build, run or check at a time"
            )
        limit = self._compiles.setdefault(session.user, RateLimit(self.limits.compiles_per_minute, 60.0))
        if not limit.allow(now):
            raise LimitError(
                f"{kind}: at most {self.limits.compiles_per_minute} compiles a minute; wait a little"
            )
        session.running = kind  # until the session process's reply tagged RUN_ENDED
        if kind in ("run", "check"):
            session.runs += 1
            if kind == "run":
                scenario = msg["scenario"]
                session.scenario = scenario.get("name") or scenario["file"]["name"]
                msg["phase"] = run_phase(self._runs)
                self._runs += 1

    def owned(self, session_id: str, user: str) -> PageSession | None:
        """The session ``session_id`` if ``user`` owns it (else None: no one sees another's)."""
        session = self.by_id.get(session_id)
        return session if session is not None and session.user == user else None

    def download(self, session_id: str, user: str, name: str) -> Path | None:
        """A file of the last run of one of ``user``'s sessions, if it exists."""
        session = self.owned(session_id, user)
        if session is None:
            return None
        path = session.folder / "out" / name
        return path if path.is_file() else None
