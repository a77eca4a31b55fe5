"""The options that say where many runs execute (``sweep``, ``grade``): ``--jobs`` local
processes, or a Dask cluster (``--dask``)."""

from __future__ import annotations

import argparse

from crslab.cli import CliError
from crslab.executors.job import Executor


def add_executor_options(p: argparse.ArgumentParser, what: str) -> None:
    """``--jobs``, ``--timeout``, ``--dask`` and ``--dask-timeout``; ``what`` is a run (``sample``,
    ``submission``) in the help texts."""
    p.add_argument(
        "--jobs", type=int, metavar="N", help=f"{what}s run at once on this machine (default: every core)"
    )
    p.add_argument(
        "--timeout",
        type=float,
        default=300.0,
        metavar="SECONDS",
        help=f"wall-clock time one {what} may take in all, building included (default: %(default)g)",
    )
    p.add_argument(
        "--dask",
        metavar="ADDRESS",
        help="run on a Dask cluster instead: a scheduler's address (tcp://host:8786), or local[:N] "
        "for a local cluster of N workers (default N: every core); needs pip install 'crslab[dask]'",
    )
    p.add_argument(
        "--dask-timeout",
        type=float,
        default=10.0,
        metavar="SECONDS",
        help="how long to wait for the Dask scheduler to answer (default: %(default)g)",
    )


def executor_from_args(args: argparse.Namespace) -> Executor:
    """The executor the options ask for; a bad option or an unreachable scheduler is a CliError."""
    if args.timeout is not None and not args.timeout > 0:
        raise CliError(f"--timeout must be > 0, got {args.timeout:g}")
    if args.dask:
        if args.jobs is not None:
            raise CliError(
                "--jobs is for this machine's processes; with --dask the cluster's workers run them"
            )
        from crslab.executors.dask_cluster import DaskError, DaskExecutor

        try:
            return DaskExecutor(args.dask, timeout_s=args.timeout, connect_timeout_s=args.dask_timeout)
        except DaskError as exc:
            raise CliError(str(exc)) from None
    from crslab.executors.local import LocalExecutor

    if args.jobs is not None and args.jobs < 1:
        raise CliError(f"--jobs must be at least 1, got {args.jobs}")
    return LocalExecutor(args.jobs, timeout_s=args.timeout)
