"""What an executor runs: a :class:`Job` (picklable, self-contained) and the :class:`Executor`
interface both executors have."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Protocol, TypeVar

from crslab.run.status import RunStatus

R = TypeVar("R")
OnDone = Callable[[int, Any], None]
"""``on_done(index, result)``: job ``index`` of the batch finished (called in the caller's thread,
in the order jobs finish)."""


class Job(Protocol):
    """One run, with everything it needs: it is pickled to the process (or the machine) that runs
    it, so it holds sources and values, never paths to the caller's files."""

    @property
    def name(self) -> str:
        """What the job is called in messages (a file name, ``sample 12``)."""
        ...

    def run(self) -> Any:
        """Do the work (in a process of its own) and return its result (picklable)."""
        ...

    def lost(self, status: RunStatus, message: str, elapsed_s: float = 0.0) -> Any:
        """The result of a job that never returned one: its process died (``crashed``), it took
        longer than allowed (``timeout``), or the Dask worker running it was lost; ``elapsed_s``:
        how long it had run when that was seen (0: not known)."""
        ...


class Executor(Protocol):
    """Runs a batch of jobs, several at once."""

    @property
    def description(self) -> str:
        """How the runs execute, for the one line the commands print (``2 local processes``)."""
        ...

    def run(self, jobs: Sequence[Job], on_done: OnDone) -> None:
        """Run every job; ``on_done(index, result)`` as each finishes. A KeyboardInterrupt stops
        what is running and propagates once every process the executor started is gone."""
        ...

    def close(self) -> None:
        """Release what the executor holds (processes, a cluster, a connection)."""
        ...
