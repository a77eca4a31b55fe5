"""``--rrd`` written by a process of its own, forked at the very start of the ``crslab`` command.

``import rerun`` costs about half a second of CPU: more than a whole 25 s tour takes with
``--fast``. A thread cannot overlap it with the crslab process's own Python work (one GIL), so
:func:`start_writer` forks a **writer process** before anything else happens (``crslab.cli.main``
calls it first, when the command line holds ``--rrd``; only the standard library and
``crslab.cli`` are imported then, and no thread runs: forking is safe). The writer imports rerun
and reads the arm's model on the other core while the crslab process parses its options, builds
the lab and forks the worker.

The crslab process then feeds a :class:`WriterSink`: it batches the calls of each chunk of ticks
and sends them, pickled, down a pipe, after which a thread of the writer unpickles them (so the
pipe never fills while rerun is still importing) and the writer hands them to a real
:class:`~crslab.sinks.rerun_scopes.RerunSink`. :meth:`WriterSink.close` waits for the writer's
answer: the recording is complete, or an error (a file that could not be written) that becomes the
same one-line error as an in-process sink's.

The writer never outlives the crslab process (it dies with it), never reads standard input nor
writes standard output, and ignores Ctrl-C (the crslab process closes the recording on an
interrupt, as it does its other files). A writer no one uses (a usage error, ``--help``,
``--rerun`` with a display, which stays in-process) is ended by :func:`discard_writer` or with the
process. Without a writer (crslab used as a library, a test calling ``main(argv)``) the
:class:`RerunSink` runs in-process, as before.

``crslab serve`` records a run's downloads the same way, in a writer forked when the run starts
(:class:`RecorderSink`: its run host or session process forks a new worker for every run and must
stay single-threaded, so it never loads rerun or pyarrow's CSV writer, both of which start
threads): the writer holds the same :class:`~crslab.sinks.rerun_scopes.RerunSink` as ``--rrd``
and the same :class:`~crslab.sinks.csv_file.CsvSink` as ``--csv``.

>>> wants_writer(["sim", "lab1.c", "--fast", "--rrd", "run.rrd"]), wants_writer(["sim", "--rrd=r.rrd"])
(True, True)
>>> wants_writer(["sim", "--csv", "run.csv"]), wants_writer(["plot", "--rrd", "x"]), wants_writer([])
(False, False, False)
"""

from __future__ import annotations

import gc
import os
import pickle
import select
import signal
import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, BinaryIO

from crslab.sinks.sink import Sink, SinkError, forwarding

if TYPE_CHECKING:  # not imported at run time: the writer is forked before numpy is loaded
    from crslab.world import World

CLOSE_TIMEOUT_S = 120.0
"""How long :meth:`WriterSink.close` waits for the writer to finish its files before ending it."""
INBOX_CHUNKS = 16
"""Chunks of ticks the writer holds unpickled before the crslab process waits for it (bounded memory)."""
COMMANDS_WITH_RRD = ("sim", "debug")
"""The commands that have ``--rrd`` (``crslab.cli.live_options.add_live_options``)."""


def wants_writer(argv: Sequence[str]) -> bool:
    """Whether a raw command line (without the program name) asks for an ``--rrd`` file."""
    if not argv or argv[0] not in COMMANDS_WITH_RRD:
        return False
    for arg in argv[1:]:
        if arg == "--":
            return False
        if arg == "--rrd" or arg.startswith("--rrd="):
            return True
    return False


class WriterProcess:
    """The crslab process's end of a writer: its pid, the pipe down to it and the one back."""

    def __init__(self, pid: int, down: BinaryIO, up: BinaryIO) -> None:
        self.pid = pid
        self.down = down
        self.up = up

    def end(self) -> None:
        """Stop a writer no one will use, and reap it."""
        for stream in (self.down, self.up):
            stream.close()
        try:
            os.kill(self.pid, signal.SIGKILL)
            os.waitpid(self.pid, 0)
        except (ProcessLookupError, ChildProcessError):
            pass


_writer: list[WriterProcess] = []


def start_writer(argv: Sequence[str]) -> None:
    """Fork the writer process when ``argv`` asks for ``--rrd``. Call it first thing in a fresh
    ``crslab`` process: before any thread starts and before anything heavy is imported."""
    if _writer or not wants_writer(argv) or threading.active_count() != 1:
        return
    _writer.append(fork_writer(preload_rerun=True))


def fork_writer(*, preload_rerun: bool) -> WriterProcess:
    """Fork a writer process now (the caller runs no other thread); ``preload_rerun``: it imports
    rerun at once, before the first chunk arrives."""
    from crslab import os_support

    down_r, down_w = os.pipe()
    up_r, up_w = os.pipe()
    os_support.enlarge_pipe(down_w)
    parent = os.getpid()
    pid = os.fork()
    if pid == 0:  # the writer
        status = 1
        try:
            os.close(down_w)
            os.close(up_r)
            _serve(down_r, up_w, parent, preload_rerun)
            status = 0
        finally:
            os._exit(status)
    os.close(down_r)
    os.close(up_w)
    return WriterProcess(pid, os.fdopen(down_w, "wb"), os.fdopen(up_r, "rb"))


def take_writer() -> WriterProcess | None:
    """The writer this process forked, for one :class:`WriterSink` to use (None: there is none)."""
    return _writer.pop() if _writer else None


def discard_writer() -> None:
    """End the writer if nothing took it (``--rerun`` with a display keeps rerun in-process)."""
    if _writer:
        _writer.pop().end()


# -- the writer's side ------------------------------------------------------------------------
def _serve(down_fd: int, up_fd: int, parent: int, preload_rerun: bool) -> None:
    from crslab import os_support

    os_support.die_with_parent()
    if os.getppid() != parent:  # the crslab process died before the line above
        return
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C: the crslab process closes the recording
    null = os.open(os.devnull, os.O_RDWR)
    os.dup2(null, 0)
    os.dup2(null, 1)  # stdout is the lab's Tera Term: never a byte from here
    os.close(null)
    import queue

    inbox: queue.Queue = queue.Queue(maxsize=INBOX_CHUNKS)

    def read() -> None:
        with os.fdopen(down_fd, "rb") as down:
            while True:
                try:
                    inbox.put(pickle.load(down))
                except Exception:  # noqa: BLE001 - end of input, or a message cut by Ctrl-C
                    inbox.put(None)
                    return

    threading.Thread(target=read, name="crslab-rrd-reader", daemon=True).start()
    if preload_rerun:
        from crslab.sinks.rerun_scopes import preload, wait_preloaded

        gc.disable()  # no collection while importing: it finds nothing to free, and takes a tenth of the time
        preload()  # import rerun now, while the crslab process starts the run
        wait_preloaded()
        gc.enable()
    sinks: list[Sink] | None = None
    notes: list[str] = []
    error: BaseException | None = None
    while (message := inbox.get()) is not None:
        kind, payload = message
        if kind == "close":
            break
        try:
            if kind == "open":
                sinks = []
                _open(sinks, **payload, on_status=notes.append)
            elif error is None and sinks is not None:
                for name, args in payload:
                    for sink in sinks:
                        getattr(sink, name)(*args)
        except Exception as exc:  # noqa: BLE001 - reported when the recording is closed
            error = error or exc
    if sinks is None:
        return
    for sink in sinks:
        try:
            sink.close()
        except Exception as exc:  # noqa: BLE001 - the first error is the one to report
            error = error or exc
    answer = {"notes": notes, "error": None}
    if isinstance(error, OSError):
        answer["error"] = ("os", error.errno, error.strerror or str(error), error.filename)
    elif error is not None:  # rerun's own errors (a RuntimeError naming the file): their first line
        answer["error"] = ("other", (str(error).strip() or type(error).__name__).splitlines()[0])
    with os.fdopen(up_fd, "wb") as up:
        pickle.dump(answer, up)


def _open(sinks: list[Sink], *, csv_path: Path | None, rrd_path: Path | None, name: str,
          world: World | None, on_status: Callable[[str], None]) -> None:
    """The writer's sinks, into ``sinks`` as each is made (so that those made are closed when the
    next one fails): ``--csv``'s, then ``--rrd``'s, set up before the first chunk arrives."""
    if csv_path is not None:
        from crslab.sinks.csv_file import CsvSink

        sinks.append(CsvSink(csv_path, world=world is not None and not world.is_free_air))
    if rrd_path is not None:
        from crslab.sinks.rerun_scopes import RerunSink

        rerun = RerunSink(rrd_path=rrd_path, name=name, on_status=on_status, world=world)
        sinks.append(rerun)
        rerun.set_up()


# -- the crslab process's side ------------------------------------------------------------------
@forwarding
class WriterSink(Sink):
    """What ``writer`` writes: a :class:`~crslab.sinks.rerun_scopes.RerunSink`'s ``rrd_path``
    and/or a :class:`~crslab.sinks.csv_file.CsvSink`'s ``csv_path``; each chunk's calls go down in
    one message after its :meth:`flush`."""

    def __init__(self, writer: WriterProcess, *, rrd_path: Path | None, csv_path: Path | None = None,
                 name: str = "crslab", on_status: Callable[[str], None] | None = None,
                 world: World | None = None) -> None:
        self.writer = writer
        self.files = " and ".join(str(p) for p in (csv_path, rrd_path) if p is not None)
        """What it writes, as an error names it."""
        self.process_name = "the rerun writer process" if rrd_path is not None else "the CSV writer process"
        self.on_status = on_status or (lambda line: None)
        self._calls: list[tuple[str, tuple]] = []
        self._broken = False
        self._closed = False
        self._send(("open", {"rrd_path": rrd_path, "csv_path": csv_path, "name": name, "world": world}))

    def _send(self, message: tuple) -> None:
        if self._broken:
            return
        try:
            pickle.dump(message, self.writer.down, protocol=pickle.HIGHEST_PROTOCOL)
            self.writer.down.flush()
        except OSError:  # the writer is gone: said once, at close
            self._broken = True

    def forward(self, name: str, args: tuple) -> None:
        """Keep the call ``name`` for the chunk's message."""
        self._calls.append((name, args))

    def on_end(self, result: object) -> None:
        """Nothing: a recording has no use for how the run ended (and it stays in this process)."""

    def flush(self) -> None:
        self._calls.append(("flush", ()))
        calls, self._calls = self._calls, []
        self._send(("calls", calls))

    def close(self) -> None:
        """Send what is left, wait for the writer to finish the file; raise its error: an
        :class:`OSError` as an in-process sink would, or a :class:`SinkError`."""
        if self._closed:
            return
        self._closed = True
        if self._calls:
            calls, self._calls = self._calls, []
            self._send(("calls", calls))
        self._send(("close", None))
        w = self.writer
        try:
            w.down.close()
        except OSError:
            self._broken = True
        answer = None
        late = not select.select([w.up], [], [], CLOSE_TIMEOUT_S)[0]
        if late:
            w.end()
        else:
            try:
                answer = pickle.load(w.up)
            except Exception:  # noqa: BLE001 - no answer: the writer died
                answer = None
            w.up.close()
            try:
                os.waitpid(w.pid, 0)
            except ChildProcessError:
                pass
        if answer is None:
            why = "did not finish in time" if late else "ended early"
            raise SinkError(f"could not finish writing {self.files}: {self.process_name} {why}")
        for line in answer["notes"]:
            self.on_status(line)
        error = answer["error"]
        if error is None:
            return
        if error[0] == "os":
            raise OSError(error[1], error[2], error[3])
        raise SinkError(f"could not finish writing {self.files}: {error[1]}")


class RecorderSink(WriterSink):
    """``crslab serve``'s downloads of a run, ``csv_path`` and/or ``rrd_path``, written by a writer
    process forked now (the caller runs no other thread); the notes of rerun are dropped."""

    def __init__(self, csv_path: Path | None, rrd_path: Path | None, name: str,
                 world: World | None = None) -> None:
        super().__init__(fork_writer(preload_rerun=rrd_path is not None), rrd_path=rrd_path,
                         csv_path=csv_path, name=name, world=world)
