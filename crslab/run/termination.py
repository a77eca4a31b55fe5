"""SIGTERM and SIGHUP (a closed terminal, ``kill``, a CI job's time-out) end a crslab command as
Ctrl-C does: the run stops between chunks, what the lab printed is kept, the serial links, the
map and the ``--pty-link`` are removed, and one line says "terminated at t = ...". The
``crslab`` command installs :func:`install` first; :class:`crslab.run.board_run.CtrlC` takes the
signals over during a run exactly as it takes SIGINT. The exit status is the shell's for the
signal (128 + its number: 143 for SIGTERM, 129 for SIGHUP).

Only the process that installed the handler raises; a child it forked (a lab's worker, a
grading process) that inherits it dies of the signal as if nothing were installed.
"""

from __future__ import annotations

import os
import signal

SIGNALS = (signal.SIGTERM, signal.SIGHUP)
_owner_pid: int | None = None
received: int | None = None
"""The terminating signal this process received, if any."""


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP arrived (``signum``); a ``KeyboardInterrupt`` so that everything that
    cleans up after Ctrl-C cleans up after it too."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum

    @property
    def name(self) -> str:
        """The signal's name, e.g. ``SIGTERM``."""
        return signal.Signals(self.signum).name


def raise_terminated(signum: int, frame: object) -> None:
    """The handler :func:`install` sets: raise :class:`Terminated` in the owner process; in a
    forked child, die of the signal."""
    global received
    if os.getpid() != _owner_pid:
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        return
    received = signum
    raise Terminated(signum)


def install() -> None:
    """Make SIGTERM and SIGHUP raise :class:`Terminated` in this process (the main thread)."""
    global _owner_pid
    _owner_pid = os.getpid()
    for signum in SIGNALS:
        if signal.getsignal(signum) is signal.SIG_DFL:
            signal.signal(signum, raise_terminated)


def exit_status(signum: int) -> int:
    """The shell's exit status for a process ended by ``signum``.

    >>> exit_status(signal.SIGTERM), exit_status(signal.SIGHUP)
    (143, 129)
    """
    return 128 + signum
