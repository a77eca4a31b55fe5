"""What a run under a debugger asks of its worker (``crslab debug``, crslab/debug/): none of it
changes what the lab computes, only who may trace it and where it stops.

>>> DebugSetup(tracer_pid=4242).trap_fp
False
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class DebugSetup:
    """The worker's side of a debugged run.

    ``tracer_pid`` is the one process allowed to trace the worker: it is named the worker's
    tracer (``PR_SET_PTRACER``, which Yama's ptrace scope 1 requires of a process that is not
    the worker's ancestor) before the sandbox closes. ``trap_fp`` turns an operation of
    ``lab()`` that makes a NaN or an infinity into SIGFPE at its line (``--debug-on-crash
    --strict``). A ``--break-when`` condition comes with the lab's build
    (:attr:`crslab.lab.build.LabBuild.break_when`).
    """

    tracer_pid: int | None = None
    trap_fp: bool = False
