"""The options that add a file output to a ``crslab sim`` or ``crslab debug`` run: one row of
:data:`SINK_OPTIONS` each, the sink itself one class in ``crslab/sinks/``.

A row names its option, what it writes (for the one-line error when it cannot: the file is tried
before anything is built), whether the sink reads the scope rows (the run then logs them), whether
it does its work in a thread of its own (:class:`~crslab.sinks.threaded.ThreadedSink`), and how
to make the sink from the option's value once the worker was forked. The live windows (rerun's
viewer, the pseudo-terminal, MuJoCo's viewer) are :mod:`crslab.cli.live_options`'s.

>>> [row.flag for row in SINK_OPTIONS]
['--transcript', '--csv']
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from crslab.cli import CliError
from crslab.output_paths import with_parent
from crslab.sinks.sink import FanOut, Sink
from crslab.sinks.threaded import ThreadedSink
from crslab.worker.config import RunConfig


@dataclass(frozen=True)
class SinkOption:
    """One option that feeds a sink: ``make(value, config)`` when the option is given."""

    flag: str
    """The long option, e.g. ``--csv``."""
    help: str
    make: Callable[[Any, RunConfig], Sink]
    metavar: str | None = "FILE"
    """None: a switch (its value is True)."""
    short: str | None = None
    writes: str | None = None
    """What the file it writes is called in an error ("the CSV"); None: it writes no file."""
    scope_rows: bool = False
    """The sink reads the run's scope rows (:meth:`~crslab.sinks.sink.Sink.on_log`)."""
    threaded: bool = False
    preload: Callable[[], None] | None = None
    """Started once the worker was forked, so that a slow import overlaps the worker's start-up."""

    @property
    def dest(self) -> str:
        """The option's attribute in the parsed arguments."""
        return self.flag.removeprefix("--").replace("-", "_")


def _transcript(path: Path, config: RunConfig) -> Sink:
    from crslab.sinks.transcript_file import TranscriptSink

    return TranscriptSink(path)


def _csv(path: Path, config: RunConfig) -> Sink:
    from crslab.sinks.csv_file import CsvSink

    return CsvSink(path, world=not config.world.is_free_air)


def _preload_csv() -> None:
    from crslab.sinks import csv_file

    csv_file.preload()


SINK_OPTIONS: list[SinkOption] = [
    SinkOption("--transcript", "save the exact bytes printed", _transcript, short="-o",
               writes="the transcript"),
    SinkOption("--csv", "write the scope signals, one row per tick, to FILE (see 'crslab plot')", _csv,
               writes="the CSV", scope_rows=True, threaded=True, preload=_preload_csv),
]
"""Every file output of a run, in the order they are fed."""


def add_sink_options(p: argparse.ArgumentParser) -> None:
    """Add every row's option to a run command's parser."""
    g = p.add_argument_group("outputs")
    for row in SINK_OPTIONS:
        flags = [row.short, row.flag] if row.short else [row.flag]
        if row.metavar is None:
            g.add_argument(*flags, action="store_true", help=row.help)
        else:
            g.add_argument(*flags, type=Path, metavar=row.metavar, help=row.help)


def asked(args: argparse.Namespace) -> list[tuple[SinkOption, Any]]:
    """The rows whose option was given, with its value."""
    return [(row, value) for row in SINK_OPTIONS if (value := getattr(args, row.dest, None))]


def writable(path: Path, what: str) -> None:
    """Fail early, in one line, when ``path`` cannot be written."""
    if path.is_dir():
        raise CliError(f"{path}: is a directory; give a file name for {what}")
    try:
        with open(with_parent(path), "ab"):
            pass
    except OSError as exc:
        raise CliError(f"{path}: cannot write {what} ({exc.strerror})") from None


def check_sinks(args: argparse.Namespace) -> None:
    """Try every file the options name (before anything is built or started)."""
    for row, value in asked(args):
        if row.writes is not None:
            writable(value, row.writes)


def sinks_need_scope_rows(args: argparse.Namespace) -> bool:
    """Whether a sink the options ask for reads the scope rows."""
    return any(row.scope_rows for row, _ in asked(args))


def preload_sinks(args: argparse.Namespace) -> None:
    """Start what the asked sinks are slow to start (the worker was just forked)."""
    for row, _ in asked(args):
        if row.preload is not None:
            row.preload()


def open_sinks(args: argparse.Namespace, config: RunConfig, out: FanOut) -> None:
    """Open the sinks the options ask for (after the worker was forked): each joins ``out``,
    which closes them."""
    for row, value in asked(args):
        try:
            sink = row.make(value, config)
        except OSError as exc:
            raise CliError(f"{value}: cannot write {row.writes or row.flag} ({exc.strerror})") from None
        out.add(ThreadedSink(sink) if row.threaded else sink)
