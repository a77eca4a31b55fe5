"""A run's CSV and ``.rrd`` for the page's downloads, written by a process of its own.

pyarrow's CSV writer and rerun start threads when they load. A session process forks a new lab
worker for every run, and forking a process that runs other threads is unsafe (a lock one of them
held stays held in the child), so the session process never loads either: before the run it
forks this recorder (while it is still single-threaded), and :class:`RecorderSink` sends it each
chunk's calls down a pipe, pickled; the recorder feeds them to crslab's own
:class:`~crslab.sinks.csv_file.CsvSink` and :class:`~crslab.sinks.rerun_scopes.RerunSink`, as
``crslab sim --csv`` and ``--rrd`` write them, and says at the end whether the files are complete.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
from multiprocessing.connection import Connection
from pathlib import Path

import numpy as np

from crslab import os_support
from crslab.sinks.sink import FanOut, Sink

CLOSE_TIMEOUT_S = 120.0


def _record(conn: Connection, csv_path: str | None, rrd_path: str | None, name: str,
            world: object | None = None) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    os_support.die_with_parent()
    sinks = FanOut()
    error = None
    try:
        if csv_path is not None:
            from crslab.sinks.csv_file import CsvSink

            sinks.add(CsvSink(Path(csv_path), world=world is not None and not world.is_free_air))  # type: ignore[attr-defined]
        if rrd_path is not None:
            from crslab.sinks.rerun_scopes import RerunSink

            rerun = RerunSink(rrd_path=Path(rrd_path), spawn=False, name=name, on_status=lambda line: None,
                              world=world)  # type: ignore[arg-type]
            rerun.prepare()
            sinks.add(rerun)
        while (calls := conn.recv()) is not None:
            for method, args in calls:
                getattr(sinks, method)(*args)
    except Exception as exc:  # noqa: BLE001 - reported to the session as one line
        error = f"the recording could not be written: {type(exc).__name__}: {exc}"
    try:
        sinks.close()
    except Exception as exc:  # noqa: BLE001
        error = error or str(exc)
    try:
        conn.send(error)
    except OSError:
        pass
    os._exit(0)


class RecorderSink(Sink):
    """Feeds a recorder process (forked now): ``csv_path`` and/or ``rrd_path``."""

    def __init__(self, csv_path: Path | None, rrd_path: Path | None, name: str,
                 world: object | None = None) -> None:
        ctx = mp.get_context("fork")
        self.conn, child = ctx.Pipe()
        self.process = ctx.Process(target=_record, args=(child, None if csv_path is None else str(csv_path),
                                                          None if rrd_path is None else str(rrd_path), name,
                                                          world))
        self.process.start()
        child.close()
        self.calls: list[tuple[str, tuple]] = []
        self.error: str | None = None

    def on_serial(self, tick: int, data: bytes) -> None:
        self.calls.append(("on_serial", (tick, data)))

    def on_print(self, tick: int, chars: int) -> None:
        self.calls.append(("on_print", (tick, chars)))

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        self.calls.append(("on_log", (columns,)))

    def flush(self) -> None:
        if self.calls:
            self.conn.send(self.calls)
            self.calls = []

    def close(self) -> None:
        """Wait for the files; a failure is an OSError naming them (as a file sink's is)."""
        try:
            self.flush()
            self.conn.send(None)
            done = self.conn.poll(CLOSE_TIMEOUT_S)
            self.error = self.conn.recv() if done else "the recorder did not finish"
        except (OSError, EOFError):
            self.error = "the recorder process ended before finishing the files"
        self.process.join(5.0)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()
        self.conn.close()
        if self.error:
            raise OSError(self.error)
