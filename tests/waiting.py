"""Waiting on events in tests: a line on a pipe, a process's exit, a thread's end.

Tests synchronize on what they wait for (a line printed, a file descriptor written, a process
gone), never on wall time: no sleeps, no "it took less than N s" bounds
(``tests/test_no_wall_clock.py`` keeps it so). Each wait has a generous timeout only as a guard
against hanging forever; when it expires the test fails with a message saying what was awaited
and what arrived meanwhile.

>>> import io
>>> pipe = LineWatcher(io.StringIO("starting\\nt = 0.5 s\\ndone\\n"), "the demo's stdout")
>>> pipe.wait_for(r"^t = ")
['starting\\n', 't = 0.5 s\\n']
>>> pipe.all()
'starting\\nt = 0.5 s\\ndone\\n'
>>> pipe.wait_for("never printed")
Traceback (most recent call last):
...
AssertionError: the demo's stdout closed before 1 line matching 'never printed' (got 0); it showed: ...
"""

from __future__ import annotations

import io
import os
import re
import select
import subprocess
import threading
import time
from collections.abc import Callable, Iterable
from typing import IO, AnyStr, Generic, TypeVar

T = TypeVar("T")

GUARD_S = 120.0
"""How long any wait may last before the test fails: only ever reached when something hangs."""


def _text(line: str | bytes) -> str:
    return line.decode(errors="replace") if isinstance(line, bytes) else line


def _shown(lines: list, last: int = 12) -> str:
    return repr("".join(_text(line) for line in lines[-last:])[-2000:])


class LineWatcher(Generic[AnyStr]):
    """Reads ``stream`` (a text or binary pipe) line by line in a thread of its own, so a test can
    wait for a line without blocking on the pipe, and later take everything the pipe carried.

    The thread is the pipe's only reader: do not read ``stream`` elsewhere (``communicate``
    included), or lines go missing.
    """

    def __init__(self, stream: IO[AnyStr], name: str) -> None:
        self.name = name
        self.lines: list[AnyStr] = []
        self.closed = False
        self._stream = stream
        self._empty: AnyStr = "" if isinstance(stream, io.TextIOBase) else b""  # type: ignore[assignment]
        self._cond = threading.Condition()
        self._thread = threading.Thread(target=self._read, name=f"watch {name}", daemon=True)
        self._thread.start()

    def _read(self) -> None:
        try:
            for line in iter(self._stream.readline, self._empty):
                with self._cond:
                    self.lines.append(line)
                    self._cond.notify_all()
        finally:
            with self._cond:
                self.closed = True
                self._cond.notify_all()

    def _matches(self, pattern: re.Pattern[str]) -> int:
        return sum(1 for line in self.lines if pattern.search(_text(line)))

    def wait_for(self, pattern: str, count: int = 1, timeout_s: float = GUARD_S) -> list[AnyStr]:
        """Block until ``count`` lines (so far) match the regular expression ``pattern``; returns
        every line read up to then. Fails if the pipe closes first or ``timeout_s`` passes."""
        regex = re.compile(pattern)
        with self._cond:
            self._cond.wait_for(lambda: self._matches(regex) >= count or self.closed, timeout_s)
            found = self._matches(regex)
            if found >= count:
                lines, n = [], 0
                for line in self.lines:
                    lines.append(line)
                    n += bool(regex.search(_text(line)))
                    if n == count:
                        return lines
            why = "closed" if self.closed else f"showed nothing more for {timeout_s:g} s"
            raise AssertionError(f"{self.name} {why} before {count} line{'s' * (count > 1)} matching "
                                 f"{pattern!r} (got {found}); it showed: {_shown(self.lines)}")

    def all(self, timeout_s: float = GUARD_S) -> AnyStr:
        """Everything the pipe carried, once its writer closed it (e.g. the process exited); closes
        the reading end."""
        self._thread.join(timeout_s)
        if self._thread.is_alive():
            raise AssertionError(f"{self.name} was still open after {timeout_s:g} s; it showed: "
                                 f"{_shown(self.lines)}")
        self._stream.close()
        return self._empty.join(self.lines)


def wait_exit(proc: subprocess.Popen, what: str, timeout_s: float = GUARD_S) -> int:
    """Wait for ``proc`` to exit and return its status; on the guard's timeout kill it and fail,
    naming ``what`` was expected to end it."""
    try:
        return proc.wait(timeout_s)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        raise AssertionError(f"the process did not exit within {timeout_s:g} s after {what}") from None


def join(thread: threading.Thread, what: str, timeout_s: float = GUARD_S) -> None:
    """Wait for ``thread`` to end; fail, naming ``what`` it was doing, if the guard expires."""
    thread.join(timeout_s)
    if thread.is_alive():
        raise AssertionError(f"{what} had not finished after {timeout_s:g} s")


def wait_until(ready: Callable[[], T | None], what: str, timeout_s: float = GUARD_S) -> T:
    """Wait until ``ready()`` gives something true (not None, False, 0 or empty) and return it: a
    state with no event to wait on (a process in or gone from /proc, a folder removed), looked at
    again every 0.05 s; fail, naming ``what`` was awaited, if the guard expires."""
    end = time.monotonic() + timeout_s
    while True:
        got = ready()
        if got:
            return got
        if time.monotonic() > end:
            raise AssertionError(f"{what}: not so after {timeout_s:g} s")
        time.sleep(0.05)


def wait_gone(pids: Iterable[int], what: str, timeout_s: float = GUARD_S) -> None:
    """Wait until every process of ``pids`` has ended (any process, not only a child: a pidfd
    becomes readable when it exits); fail, naming ``what`` should have ended them."""
    end = time.monotonic() + timeout_s
    for pid in pids:
        try:
            fd = os.pidfd_open(pid)
        except ProcessLookupError:
            continue
        try:
            if not select.select([fd], [], [], max(0.0, end - time.monotonic()))[0]:
                raise AssertionError(f"process {pid} still runs {timeout_s:g} s after {what}")
        finally:
            os.close(fd)
