"""Run jobs in processes of this machine, ``workers`` at a time (``--jobs``).

Each job runs in a fresh process forked from a single-threaded fork server that has crslab
already imported, so starting one costs a few milliseconds, the process may then fork the lab's
own worker safely, and one job's crash (or a crslab bug it triggers) never touches another. A
process that dies without answering is its job's ``lost(crashed)``; one that takes longer than
``timeout_s`` in all is killed and is its job's ``lost(timeout)``, with the time it ran. Ctrl-C
kills every process still running and propagates as KeyboardInterrupt, between two jobs' results.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import shutil
import signal
import tempfile
import threading
import time
from collections.abc import Sequence
from multiprocessing.connection import Connection, wait
from typing import Any

from crslab import os_support
from crslab.executors.job import Job, OnDone
from crslab.run.status import RunStatus

DEFAULT_TIMEOUT_S = 300.0
"""Wall-clock time one job may take in all (building included), by default."""
PRELOAD = ["crslab.executors.local", "crslab.regress.grade", "crslab.regress.runner", "crslab.lab.build",
           "crslab.sweep.sample_job", "crslab.worker.main", "crslab.sandbox.run_sandbox",
           "crslab.executors.warmup"]
"""Modules the fork server imports once, so that no job process, and no lab worker it forks,
imports them again (MuJoCo's import alone costs more than a short run)."""


def default_workers() -> int:
    """Every core this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def context() -> mp.context.BaseContext:
    """The fork server (each job's process starts from a clean single-threaded server, which may
    then fork the lab's own worker safely), else spawn."""
    return os_support.fork_server(PRELOAD)


def _child(conn: Connection, job: Job, scratch: str) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the process that started us's to handle
    os_support.die_with_parent()
    # every temporary file of the job (a submission's private copy, a sanitizer's report) goes into
    # the folder the executor removes when the job ends, however it ends
    os.environ["TMPDIR"] = scratch
    tempfile.tempdir = scratch
    try:
        result = job.run()
    except Exception as exc:  # noqa: BLE001 - reported as this job's crash, never raised
        result = job.lost(RunStatus.CRASHED, f"{job.name}: crslab failed: {type(exc).__name__}: {exc}")
    try:
        conn.send(result)
        conn.close()
    except OSError:  # the batch was stopped (Ctrl-C) while this job finished: nobody reads it
        pass


class LocalExecutor:
    """``workers`` job processes at a time on this machine."""

    def __init__(self, workers: int | None = None, *, timeout_s: float = DEFAULT_TIMEOUT_S,
                 cancel: threading.Event | None = None) -> None:
        self.workers = max(1, workers if workers is not None else default_workers())
        self.timeout_s = timeout_s
        self.cancel = cancel
        """When set (from another thread), the batch stops: its processes are killed and
        KeyboardInterrupt is raised, as for Ctrl-C."""

    @property
    def description(self) -> str:
        return f"{self.workers} at a time"

    def close(self) -> None:
        """Nothing is held between batches."""

    def run(self, jobs: Sequence[Job], on_done: OnDone) -> None:
        with _CtrlCFlag() as ctrl_c:
            self._run(jobs, on_done, ctrl_c)

    def _run(self, jobs: Sequence[Job], on_done: OnDone, ctrl_c: threading.Event) -> None:
        ctx = context()
        pending = list(enumerate(jobs))
        running: dict[Connection, tuple[int, mp.process.BaseProcess, float]] = {}
        scratch: dict[Connection, str] = {}

        def finish(conn: Connection, result: Any) -> None:
            index, proc, _ = running.pop(conn)
            conn.close()
            proc.join(5.0)
            if proc.is_alive():
                proc.kill()
                proc.join()
            shutil.rmtree(scratch.pop(conn), ignore_errors=True)
            on_done(index, result)

        try:
            while pending or running:
                if ctrl_c.is_set() or (self.cancel is not None and self.cancel.is_set()):
                    raise KeyboardInterrupt
                while pending and len(running) < self.workers:
                    index, job = pending.pop(0)
                    parent, child = ctx.Pipe(duplex=False)
                    folder = tempfile.mkdtemp(prefix="crslab-job-")
                    proc = ctx.Process(target=_child, args=(child, job, folder), name=f"crslab {job.name}")
                    proc.start()
                    running[parent] = (index, proc, time.monotonic())
                    scratch[parent] = folder
                    child.close()
                for conn in wait(list(running), timeout=0.2):
                    assert isinstance(conn, Connection)
                    index, proc, _ = running[conn]
                    try:
                        result = conn.recv()
                    except (EOFError, OSError):
                        proc.join(1.0)
                        job = jobs[index]
                        ran_s = time.monotonic() - running[conn][2]
                        result = job.lost(RunStatus.CRASHED, f"{job.name}: its process died "
                                          f"(exit status {proc.exitcode})", ran_s)
                    finish(conn, result)
                now = time.monotonic()
                for conn, (index, proc, started) in list(running.items()):
                    if now - started > self.timeout_s:
                        proc.kill()
                        job = jobs[index]
                        finish(conn, job.lost(RunStatus.TIMEOUT, f"{job.name} took longer than "
                                              f"{self.timeout_s:g} s in all and was stopped",
                                              time.monotonic() - started))
        finally:
            for conn, (_, proc, _) in running.items():
                if proc.pid is not None:
                    proc.kill()
                    proc.join()
                conn.close()
                if conn in scratch:
                    shutil.rmtree(scratch.pop(conn), ignore_errors=True)


class _CtrlCFlag(threading.Event):
    """Ctrl-C (SIGINT) during a batch, in the main thread, only sets this flag; the batch loop
    sees it within one turn (0.2 s) and stops there with KeyboardInterrupt. So no Ctrl-C ever
    lands in the middle of starting a process or of the caller's ``on_done`` (a row half
    written). Elsewhere (another thread, a handler of the caller's own) SIGINT is left alone."""

    def __enter__(self) -> _CtrlCFlag:
        self._old: object = None
        if (threading.current_thread() is threading.main_thread()
                and signal.getsignal(signal.SIGINT) is signal.default_int_handler):
            self._old = signal.signal(signal.SIGINT, lambda signum, frame: self.set())
        return self

    def __exit__(self, *exc: object) -> None:
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)


def run_alone(job: Job, timeout_s: float = DEFAULT_TIMEOUT_S, cancel: threading.Event | None = None) -> Any:
    """Run one job in a process of its own and return its result (a Dask task does this)."""
    results: list[Any] = []
    LocalExecutor(1, timeout_s=timeout_s, cancel=cancel).run([job], lambda _, result: results.append(result))
    return results[0]
