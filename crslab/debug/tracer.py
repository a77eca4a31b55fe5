"""The debugger process of a debugged run, started before the lab's worker and held until the
worker is ready.

The worker names the one process allowed to trace it (``PR_SET_PTRACER``, needed under Yama's
ptrace scope 1, where a process may trace only its descendants and the debugger is the worker's
sibling) before its sandbox closes, so that process must exist first. A tiny Python gate starts
now, waits for the worker's process id on a pipe, then ``exec``s the debugger with it: same
process, so the id the worker named is the debugger's.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from collections.abc import Sequence
from typing import IO

from crslab import os_support

ATTACH_TIMEOUT_S = 120.0
_GATE = (
    "import os, signal, sys\n"
    "signal.signal(signal.SIGINT, signal.SIG_DFL)\n"
    "fd = int(sys.argv[1])\n"
    "pid = os.read(fd, 32).decode().strip()\n"
    "os.close(fd)\n"
    "if not pid.isdigit():\n"
    "    sys.exit(70)\n"
    "os.execv(sys.argv[2], sys.argv[2:] + [pid])\n"
)


class TracerError(RuntimeError):
    """The debugger did not attach; the message says why in one line."""


class GatedTracer:
    """``argv`` (the debugger's full path first) run with the worker's process id appended, once
    :meth:`release` gives it. ``own_session`` keeps it away from the terminal's Ctrl-C (gdbserver);
    gdb on the console shares the terminal with crslab."""

    def __init__(self, argv: Sequence[str], *, own_session: bool = False, stdin: int | IO | None = None,
                 stdout: int | IO | None = None, stderr: int | IO | None = None) -> None:
        self.name = os.path.basename(argv[0])
        read_end, self._gate = os.pipe()
        try:
            self.process = subprocess.Popen([sys.executable, "-I", "-c", _GATE, str(read_end), *argv],
                                            pass_fds=(read_end,), stdin=stdin, stdout=stdout, stderr=stderr,
                                            start_new_session=own_session)
        finally:
            os.close(read_end)

    @property
    def pid(self) -> int:
        """The debugger's process id (the gate's, which becomes the debugger)."""
        return self.process.pid

    @property
    def running(self) -> bool:
        """Whether the debugger process is still there."""
        return self.process.poll() is None

    def release(self, worker_pid: int) -> None:
        """Start the debugger on ``worker_pid``."""
        try:
            os.write(self._gate, f"{worker_pid}\n".encode())
        finally:
            self._close_gate()

    def wait_attached(self, worker_pid: int, timeout_s: float = ATTACH_TIMEOUT_S) -> None:
        """Return once the debugger traces ``worker_pid``: from then on the worker runs only when
        the debugger lets it. Raises :class:`TracerError` if it exits or takes too long."""
        deadline = time.monotonic() + timeout_s
        while True:
            tracer = os_support.tracer_of(worker_pid)
            if tracer == self.pid:
                return
            if self.process.poll() is not None:
                hint = os_support.ptrace_restriction()
                raise TracerError(f"{self.name} could not attach to the lab's process (it exited with status "
                                  f"{self.process.returncode}{'; ' + hint if hint else ''})")
            if tracer is None:
                raise TracerError(f"the lab's process ended before {self.name} attached")
            if time.monotonic() > deadline:
                raise TracerError(f"{self.name} did not attach to the lab's process within {timeout_s:g} s")
            time.sleep(0.02)

    def stop(self, grace_s: float = 5.0) -> None:
        """End the debugger (if it still runs): SIGTERM, then SIGKILL after ``grace_s``."""
        self._close_gate()
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(grace_s)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()

    def _close_gate(self) -> None:
        if self._gate >= 0:
            os.close(self._gate)
            self._gate = -1
