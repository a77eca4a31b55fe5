"""The server's table of page sessions (crslab/serve/page_sessions.py) without their processes:
a session that only the table keeps, and a table whose start forks nothing, for the tests of what
the table admits and holds while threads change it."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from crslab.serve.page_sessions import PageSession, Sessions


class _Process:
    """What a session's process must answer when the session closes."""

    def terminate(self) -> None:
        pass

    def join(self, timeout: float | None = None) -> None:
        pass

    def is_alive(self) -> bool:
        return False


class _Conn:
    def close(self) -> None:
        pass


def table_session(name: str, user: str, folder: Path) -> PageSession:
    """A session as the table keeps it, with no process behind it."""
    return PageSession(name, user, _Process(), _Conn(), folder)  # type: ignore[arg-type]


def start_without_processes(monkeypatch, sessions: Sessions,  # noqa: ANN001 - pytest's monkeypatch
                            start: Callable[[str], PageSession]) -> None:
    """Make ``sessions`` start a user's page with ``start(user)`` (which forks nothing) and no
    fork server."""
    monkeypatch.setattr(sessions, "_start", start)
    sessions._ctx = object()  # type: ignore[assignment]
