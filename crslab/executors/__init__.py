"""Where many runs execute: a pool of local processes, or a Dask cluster.

``crslab sweep`` and ``crslab grade`` hand their runs to an executor as :class:`Job` values: each
job carries everything its run needs (the lab's source, not a path), runs in a process of its
own, and comes back as one result in the order the executor's caller chose, whichever executor
ran it. A job whose process dies, or that takes longer than allowed, comes back as what
:meth:`Job.lost` makes of that: a row or a grade with its status, never a lost batch.

- :mod:`crslab.executors.local`: ``--jobs N`` processes on this machine (the default);
- :mod:`crslab.executors.dask_cluster`: ``--dask ADDRESS`` (an existing scheduler) or
  ``--dask local[:N]`` (a LocalCluster of N workers in this process, on the loopback).
"""

from crslab.executors.job import Executor, Job, OnDone

__all__ = ["Executor", "Job", "OnDone"]
