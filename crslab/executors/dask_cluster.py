"""Run jobs on a Dask distributed cluster: ``--dask ADDRESS`` (a running scheduler, e.g. one
that dask-jobqueue started on a Slurm or PBS cluster) or ``--dask local[:N]`` (a LocalCluster of
N workers, default every core, started in this process and listening on the loopback only).

Each job is one Dask task that runs the job in a process of its own on the worker
(:func:`crslab.executors.local.run_alone`), with the same timeout as the local pool: the task
carries the lab's source, so workers need no shared file system, and each worker machine builds
a lab once (its own build cache). A worker that dies while running a task makes Dask run it again
elsewhere; when Dask gives up (``KilledWorker``), the job comes back as ``lost(crashed)``. Workers
need crslab installed (``pip install 'crslab[dask]'``), the same version as here.
"""

from __future__ import annotations

import logging
import multiprocessing as mp
import re
import threading
import uuid
from collections.abc import Sequence
from typing import Any

from crslab.executors.job import Job, OnDone
from crslab.executors.local import DEFAULT_TIMEOUT_S, default_workers, run_alone
from crslab.run.status import RunStatus

CONNECT_TIMEOUT_S = 10.0
"""How long to wait for a scheduler to answer, by default."""
INSTALL_HINT = "pip install 'crslab[dask]'"
_LOCAL = re.compile(r"^local(?::(\d+))?$")
CANCEL = threading.Event()
"""Set while a batch on an in-process cluster is being cancelled (Ctrl-C): its workers' jobs stop."""


class DaskError(Exception):
    """Dask is missing, or the scheduler cannot be reached: one line for the user (exit 2)."""


def parse_local(address: str) -> int | None:
    """The worker count of ``local`` / ``local:N`` (every core for ``local``), None for a
    scheduler's address.

    >>> parse_local("local:2"), parse_local("tcp://10.0.0.5:8786")
    (2, None)
    """
    m = _LOCAL.match(address.strip())
    if m is None:
        return None
    return int(m.group(1)) if m.group(1) else default_workers()


def _run_task(job: Job, timeout_s: float) -> Any:
    """The Dask task: run ``job`` in a process of its own on this worker."""
    process = mp.current_process()
    if process.daemon:
        # A Dask worker process is daemonic by default, and multiprocessing refuses children to
        # daemonic processes (they could outlive it). Job processes cannot: they ask the kernel to
        # kill them when their parent dies (os_support.die_with_parent), as does the lab's worker.
        process._config["daemon"] = False  # type: ignore[attr-defined]
    return run_alone(job, timeout_s, cancel=CANCEL)


class DaskExecutor:
    """Jobs as tasks on a Dask cluster."""

    def __init__(self, address: str, *, timeout_s: float = DEFAULT_TIMEOUT_S,
                 connect_timeout_s: float = CONNECT_TIMEOUT_S) -> None:
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError:
            raise DaskError(f"--dask needs Dask's distributed scheduler: {INSTALL_HINT}") from None
        logging.getLogger("distributed").setLevel(logging.ERROR)
        self.timeout_s = timeout_s
        self.cluster = None
        workers = parse_local(address)
        if workers is not None:
            if workers < 1:
                raise DaskError(f"--dask {address}: a local cluster needs at least 1 worker")
            # threads, not processes: each job runs in a process of its own anyway, and the
            # cluster starts at once; tcp on the loopback, so tasks are pickled as on a real one
            self.cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=False,
                                        protocol="tcp", host="127.0.0.1", dashboard_address="127.0.0.1:0",
                                        silence_logs=logging.ERROR)
            self.client = Client(self.cluster, set_as_default=False)
            self._description = f"on a local Dask cluster of {workers} worker{'s' * (workers > 1)}"
        else:
            try:
                self.client = Client(address, timeout=connect_timeout_s, set_as_default=False)
            except (OSError, TimeoutError, ValueError) as exc:
                why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
                raise DaskError(f"--dask {address}: the Dask scheduler cannot be reached ({why})") from None
            n = len(self.client.scheduler_info().get("workers", {}))
            self._description = f"on the Dask cluster at {address} ({n} worker{'s' * (n != 1)} now)"

    @property
    def description(self) -> str:
        return self._description

    def run(self, jobs: Sequence[Job], on_done: OnDone) -> None:
        from dask.distributed import as_completed
        from distributed import KilledWorker

        batch = uuid.uuid4().hex[:8]
        futures = [self.client.submit(_run_task, job, self.timeout_s, key=f"crslab-{batch}-{i}", pure=False)
                   for i, job in enumerate(jobs)]
        index = {f.key: i for i, f in enumerate(futures)}
        try:
            for future in as_completed(futures, loop=self.client.loop):
                i = index[future.key]
                job = jobs[i]
                try:
                    result = future.result()
                except KilledWorker:
                    result = job.lost(RunStatus.CRASHED, f"{job.name}: the Dask workers running it died")
                except Exception as exc:  # noqa: BLE001 - a task Dask could not run is that job's row
                    result = job.lost(RunStatus.CRASHED, f"{job.name}: Dask could not run it: "
                                      f"{type(exc).__name__}: {exc}")
                on_done(i, result)
        except KeyboardInterrupt:
            if self.cluster is not None:
                CANCEL.set()  # this process's workers stop their jobs' processes
            self.client.cancel(futures)
            raise

    def close(self) -> None:
        """Disconnect (and stop the local cluster)."""
        try:
            self.client.close()
            if self.cluster is not None:
                self.cluster.close()
        finally:
            CANCEL.clear()
