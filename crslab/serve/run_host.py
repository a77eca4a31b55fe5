"""A run host: the process that runs many pages' labs, each an instance of one board worker, and
produces their pages' messages itself.

``crslab serve`` starts a few of them (about one per core: :mod:`crslab.serve.run_hosts`). A page's
session process builds its lab and prepares the run (:class:`HostedRun`); the server hands it to a
host, which opens it as an instance of its worker (:class:`crslab.run.board_run.BoardRun` on a
shared :class:`~crslab.run.board_client.BoardClient`), paces it with the one pacer
(:class:`~crslab.run.pacing.Pacer`, the page's chunks), and after each chunk hands it to the run's
sinks (the page's stream, the transcript, the recorder) as ``crslab sim`` does
(:class:`~crslab.run.board_run.ChunkedRun`). A chunk is due :data:`LEAD_S` before the wall clock
reaches its first tick (the page plays it from then on), and one wake-up runs every run of the
worker that is due (within :data:`BATCH_S`, :data:`ACTING_BATCH_S` while its page acts) in one
request. The page's commands (stop, speed, vars, hand, release) reach the run between two chunks,
as they arrive.

The pipe to the server (:mod:`crslab.serve.wire`): in, the server's requests (a run, a page's
command, a page gone); out, one frame per page message (:func:`~crslab.serve.wire.host_frame`).
The page messages of one wake-up go out together, in one write once the wake-up is done
(:meth:`RunHost.flush`): the server is woken once for them, not once for each while the host is
still running the others (on two cores, each write handed the core to the server, and the
host's other runs waited for it).
"""

from __future__ import annotations

import dataclasses
import gc
import itertools
import math
import os
import pickle
import select
import signal
import socket
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from multiprocessing.connection import Connection
from pathlib import Path

from crslab import os_support
from crslab._bindings import constants
from crslab.contest.offsets import Rest
from crslab.contest.page_card import ContestCardSink
from crslab.contest.run import CHUNK_TICKS as CONTEST_LOOK_TICKS
from crslab.contest.run import MotionWatch
from crslab.framework_facts import TICKS_PER_S
from crslab.live.console import VarConsole
from crslab.run import diagnosis
from crslab.run.assemble import NoLab
from crslab.run.board_client import BoardClient
from crslab.run.board_run import DEFAULT_DEADLINE_S, BoardRun, ChunkedRun, Limits, RunError
from crslab.run.diagnosis import Ending
from crslab.run.pacing import PAGE_CHUNKS, Pacer
from crslab.run.status import RunResult, RunStatus
from crslab.run.worker_process import Wake
from crslab.serve import wire
from crslab.serve.page_text import PageText
from crslab.serve.stream import PageControl, Stopped
from crslab.sinks.page_stream import SCOPE_EVERY_TICKS, ArmPoses, BrowserStream, message
from crslab.sinks.sink import FanOut, SinkError
from crslab.sinks.transcript_file import TranscriptSink
from crslab.worker.config import RunConfig
from crslab.worker.run_stats import RunStats
from crslab.worker.share import HOST_SHARE, Share, board_ms
from crslab.worker.worker_messages import Ran
from crslab.world import World

SEND_BUFFER_BYTES = 4 << 20
"""The host's side of its pipe to the server buffers this much (as far as the system allows)."""
BATCH_S = 0.06
"""A wake-up runs every run due within this much of now (s), in one request to the worker, the one
due first first: a run's chunk is then made up to this much earlier than it is due (its ticks and
the page's messages are the same), and a host with 50 runs at real time wakes some 15 times a
second for 13 chunks, not 100 times for 2 (each wake-up costs the host and the worker a few system
calls and cold caches: on two cores, 30 ms instead of none took a fifth off the hosts' and workers'
CPU per session, 60 ms instead of 30 another 5 %). A run whose page acts (its chunks are 20 ms:
:class:`~crslab.serve.stream.PageControl`) waits for :data:`ACTING_BATCH_S` only, so that the
hand's push is not made further ahead of what the page shows."""
ACTING_BATCH_S = 0.03
"""A wake-up's window (s) for a run whose page acts (:data:`BATCH_S`)."""
CUT_REST_S = 0.08
"""A run whose chunk had its share of the host (:mod:`crslab.worker.share`: it ended at 10 ms of the
worker's CPU) and is behind its pace gets its next chunk this long after (s): a run that costs more
than real time (x its speed) takes at most a fifth of its host, and goes on slower."""
FLUSH_S = 0.005
"""A page message waits at most this long (s) for the others of its wake-up before they are written
to the server together."""
LEAD_S = 0.03
"""A run's chunk is due this long before the wall clock reaches its first tick (s): the page gets
it ahead of its time, as its playout needs, though the host runs its other runs' chunks first."""
PROCESS_NAME = "crslab-host"
"""What ``ps`` calls a run host (its board worker is its child)."""
DOWNLOADS = {"transcript": "transcript.txt", "csv": "run.csv", "rrd": "run.rrd"}
"""The files of the last run a page may download, by kind."""


@dataclass(frozen=True)
class HostedRun:
    """A run a session process prepared for a host: the configuration (the lab built), the end
    tick, the speed and the run's phase, the notes for ``started``, the session's folder (its
    outputs go to ``out/``), what to record, and the run's limits."""

    config: RunConfig
    end_tick: int
    speed: float | None
    phase: float
    notes: tuple[str, ...]
    folder: Path
    record_csv: bool = False
    record_rrd: bool = False
    output_bytes: int = 16 * 1024 * 1024
    contest: Rest | None = None
    """A contest run (the page's ``contest``), resting there: it sends its scorecard before
    ``ended`` (crslab/contest/) and, ``until_still``, ends once the arm's motion has."""
    until_still: bool = False


class HostedSession:
    """One page's run in the host: its lab (a board instance), its sinks, its pacer and control."""

    def __init__(self, host: RunHost, key: str, run: HostedRun) -> None:
        self.host = host
        self.key = key
        self.run = run
        self.page_text = PageText(run.folder)
        self.sim: BoardRun | None = None
        self.chunked: ChunkedRun | None = None
        self.control: PageControl | None = None
        self.out = FanOut()
        self.notes = list(run.notes)
        self.due_s = 0.0
        self.cut = False
        """The last chunk ended at the run's share of the host (``CRS_RUN_CUT``)."""
        self.before = RunStats()
        """The run's counters before its last chunk."""
        self.slowed = False
        self.behind = False
        """The last chunk was cut and left the run behind its pace: it goes on slowed."""
        self.turn = 0
        """The host's wake-up that last ran it (:func:`in_turn`)."""
        self.window_s = BATCH_S
        """How early a wake-up runs its next chunk (:data:`BATCH_S`, :data:`ACTING_BATCH_S`)."""
        self.motion: MotionWatch | None = None
        """A contest run's watch on the arm's motion (it ends the run once the motion has)."""

    def send(self, data: bytes, tag: bytes = wire.FORWARD) -> None:
        """A message for the page (no server path in it: :mod:`crslab.serve.page_text`)."""
        self.host.send_frame(wire.host_frame(self.key, tag, self.page_text.message(data)))

    def open(self) -> bool:
        """Open the lab as an instance, start the sinks and say ``started``; False when the run
        ended at once (its ``ended`` sent)."""
        run, config = self.run, self.run.config
        if not (run.record_csv or run.record_rrd):  # the page's scopes need every 5th tick only
            config = dataclasses.replace(config, log_every_ticks=SCOPE_EVERY_TICKS)
        try:
            self.sim = self.host.simulation(config, Limits(output_bytes=run.output_bytes))
        except RunError as exc:
            self.ended(RunResult(exc.status, 0, str(exc)))
            return False
        name = config.build.source.name
        if not self.sim.defines_lab:  # refused before any tick, as crslab sim refuses it
            refused = NoLab(name)
            self.close()
            self.ended(RunResult(refused.status, 0, str(refused)))
            return False
        out_dir = run.folder / "out"
        stream = BrowserStream(self.send, self.host.arm_in(config.world), world=not config.world.is_free_air)
        self.out.add(stream)
        self.out.add(TranscriptSink(out_dir / DOWNLOADS["transcript"]))
        if run.until_still:
            self.motion = MotionWatch(config.startup_ticks)
            self.out.add(self.motion)
        if run.contest is not None:
            self.out.add(ContestCardSink(self.send, config.world, run.contest, config.startup_ticks,
                                         config.budget_instructions))
        recording = run.record_csv or run.record_rrd
        if recording:
            from crslab.sinks.rerun_writer import RecorderSink

            self.host.closed()  # forked now: no other thread of the host runs (a recorder closing)
            self.out.add(RecorderSink(out_dir / DOWNLOADS["csv"] if run.record_csv else None,
                                      out_dir / DOWNLOADS["rrd"] if run.record_rrd else None, name,
                                      config.world))
        pacer = Pacer(run.speed, 0, chunks=PAGE_CHUNKS, phase=run.phase)
        self.control = PageControl(self.send, stream, VarConsole(config.build.watched), pacer, self._busy)
        self.chunked = self.sim.start(run.end_tick, self.out, pacer, [self.control])
        if config.log_signals and self.motion is None and run.contest is None and not recording:
            # the page's stream is the only sink that takes rows: it packs them from the block
            self.chunked.rows_in_block = True
            stream.rows_from(self.sim.block)
        events = [{"tick": e.tick, "text": e.describe()} for e in config.scenario.events]
        contest = None if run.contest is None else {"band_g": list(config.world.contest.band_g),
                                                    "rest_motor_rad": list(run.contest.motor_rad),
                                                    "rest": run.contest.line()}
        self.send(message("started", end_tick=run.end_tick, scenario=config.scenario.name, speed=run.speed,
                          events=events, notes=self.notes, due_monotonic=pacer.wall0,
                          watched=[v.name for v in config.build.watched], contest=contest), wire.RUN_STARTED)
        self.due_s = pacer.due_s(0) - LEAD_S
        return True

    def _busy(self, msg: dict) -> None:
        self.send(message("error", message=f"{msg.get('type')}: a run is going on; stop it first"))

    def command(self, msg: dict) -> bool:
        """Carry out a command of the page now; False when it ended the run."""
        assert self.sim is not None and self.control is not None and self.chunked is not None
        try:
            self.control.command(self.sim, msg)
            self.control.serve(self.sim)  # the hand's push, at once
        except Stopped:
            self.finish(diagnosis.stopped(self.sim.tick))
            return False
        except RunError as exc:
            self.finish(Ending(RunStatus.CRASHED, self.sim.tick, str(exc)))
            return False
        self.due_s = self.chunked.pacer.due_s(self.sim.tick) - LEAD_S  # a new speed paces from now
        self.window_s = self._window_s()
        return True

    def _window_s(self) -> float:
        """The run's :attr:`window_s`: short while its page acts (its chunks are short)."""
        control = self.control
        acting = control is not None and control.chunk_ticks(control.speed) is not None
        return ACTING_BATCH_S if acting else BATCH_S

    def take(self, reply: object) -> Ending | None:
        """Hand a chunk's reply to the sinks (its controls wait for :meth:`after`: the worker may
        still be running the host's other chunks); how the run ended, or None."""
        assert self.chunked is not None and self.sim is not None
        self.before = self.sim.stats
        ending = self.chunked.took(reply, serve=False)  # type: ignore[arg-type]
        self.cut = isinstance(reply, Ran) and reply.code == constants.CRS_RUN_CUT
        still = self.motion is not None and self.motion.ended and self.sim.tick % CONTEST_LOOK_TICKS == 0
        if ending is None and (self.chunked.done or still):
            ending = Ending(RunStatus.OK, self.sim.tick)  # (a contest run: the arm has come to rest)
        return ending

    def next_target(self) -> int:
        """Where the run's next chunk ends: its pacer's, but a contest run's never past the next
        tick ``crslab contest`` looks at the motion at (a chunk cut at the run's share ends
        anywhere): it ends at the tick ``crslab contest`` ends it at."""
        assert self.chunked is not None and self.sim is not None
        target = self.chunked.next_chunk()[0]
        if self.motion is not None:
            target = min(target, (self.sim.tick // CONTEST_LOOK_TICKS + 1) * CONTEST_LOOK_TICKS)
        return target

    def after(self, ending: Ending | None) -> bool:
        """After the worker's request: end the run (``ending``), or serve its control and say
        when its next chunk is due; False when it ended."""
        assert self.chunked is not None and self.sim is not None
        if ending is not None:
            self.finish(ending)
            return False
        self.chunked.serve_controls()
        pacer = self.chunked.pacer
        self.due_s = pacer.due_s(self.sim.tick) - LEAD_S
        self.window_s = self._window_s()
        self.behind = self.cut and pacer.speed is not None and self.due_s <= time.monotonic()
        if self.behind:
            # it had its share of the host and is behind its pace: it costs more than real time (x
            # its speed), so it goes on later, slower (as fast as possible, it just goes on)
            self.due_s = time.monotonic() + CUT_REST_S
            pacer.restart(self.sim.tick, at_s=self.due_s + LEAD_S)
            if not self.slowed:
                self.slowed = True
                self.slow_note(self.before, self.sim.stats)
        return True

    @property
    def background(self) -> bool:
        """Whether the run goes in the background (:func:`in_turn`): as fast as possible, or slowed."""
        return self.behind or self.chunked is None or self.chunked.pacer.speed is None

    def slow_note(self, before: RunStats, after: RunStats) -> None:
        """Tell the page, once, that its run goes slower than real time (x the speed it asked for),
        and why: its lab (what a tick of it would take the board) or a busy server."""
        calls = after.lab_calls - before.lab_calls
        per_call = (after.lab_cost_total - before.lab_cost_total) / calls if calls else 0.0
        name = self.run.config.build.source.name
        tick_ms = 1000 / TICKS_PER_S
        if board_ms(round(per_call)) > tick_ms:
            why = (f"{name}'s lab() costs {per_call:,.0f} instructions a call: the F28335 would need "
                   f"{board_ms(round(per_call)):g} ms for each, and it calls lab() every {tick_ms:g} ms, so "
                   "the board would miss its timer ticks")
        else:
            why = "this server is busy"
        speed = self.chunked.pacer.speed if self.chunked is not None else None
        pace = "real time" if speed in (None, 1.0) else f"{speed:g}x real time"
        note = f"{why}; the run goes on slower than {pace}, so that the server's other runs keep theirs"
        self.notes.append(note)
        self.send(message("note", tick=self.sim.tick if self.sim is not None else 0, text=note))

    def finish(self, ending: Ending) -> None:
        """The run ended: its last bytes to the sinks, the instance closed, ``ended`` sent once
        the sinks are closed (a recorder's files written: in a thread of the host's, so that
        writing them holds none of its other runs back)."""
        assert self.chunked is not None
        result = self.chunked.ended(ending)
        self.out.flush()  # the bytes still on the serial line as it ended: the page shows them too
        self.close(then=lambda: self.ended(result))

    def close(self, then: Callable[[], None] | None = None) -> None:
        """Close the instance and the sinks (a sink's failure becomes a note), then call
        ``then()``; a recording run's sinks close in a thread of the host's (:meth:`RunHost.aside`)."""
        if self.sim is not None:
            self.sim.close()
            self.sim = None
        out, self.out = self.out, FanOut()

        def close_sinks() -> None:
            try:
                out.close()
            except SinkError as exc:
                self.notes.append(str(exc))
            if then is not None:
                then()

        if self.run.record_csv or self.run.record_rrd:
            self.host.aside(close_sinks)
        else:
            close_sinks()

    def ended(self, result: RunResult) -> None:
        failed = [line for e in result.failed_expectations for line in e.lines()]
        out_dir = self.run.folder / "out"
        downloads = [kind for kind, name in DOWNLOADS.items() if (out_dir / name).exists()]
        said = wire.ended(result.status, result.message, end_tick=result.end_tick, failed_expectations=failed,
                          notes=self.notes, downloads=downloads)
        self.send(said, wire.RUN_ENDED)


class RunHost:
    """The host's runs by session key, and the loop that paces them (:meth:`serve`). Each run may
    take ``share`` of the host's worker (:mod:`crslab.worker.share`) and a call of its lab
    ``deadline_s`` (None: no deadline)."""

    def __init__(self, conn: Connection, share: Share = HOST_SHARE,
                 deadline_s: float | None = DEFAULT_DEADLINE_S) -> None:
        self.conn = conn
        self.share = share
        self.deadline_s = deadline_s
        self.sessions: dict[str, HostedSession] = {}
        self.worker: BoardClient | None = None
        """The board worker every run of this host is an instance of."""
        self._arms: dict[str, ArmPoses] = {}
        self._send_lock = threading.Lock()
        self._out: list[bytes] = []
        """The page messages of this wake-up, framed, not yet written (:meth:`flush`)."""
        self._held_since = 0.0
        self._loop = threading.get_ident()
        """The thread of :meth:`serve`'s loop: its messages wait for :meth:`flush`."""
        self._aside: list[threading.Thread] = []
        self._pipe = select.poll()  # one for the host's life (Connection.poll makes a selector every call)
        self._pipe.register(conn.fileno(), select.POLLIN)
        self._turns = itertools.count(1)  # each wake-up's number: a session's turn is its last
        self._arrived: deque[tuple] = deque()
        """The server's messages that came while the worker ran, not yet carried out."""
        self._server_gone = False

    def send_frame(self, data: bytes) -> None:
        """One page message to the server: written with the others of this wake-up
        (:meth:`flush`), or once the first of them has waited :data:`FLUSH_S` (a long wake-up's
        first chunks do not wait for its last), or at once when a thread of the host's sends it (a
        recorder closing)."""
        with self._send_lock:
            now = time.monotonic()
            if not self._out:
                self._held_since = now
            self._out.append(wire.length_prefixed(data))
            if threading.get_ident() != self._loop or now - self._held_since >= FLUSH_S:
                self._write()

    def flush(self) -> None:
        """Write the page messages of this wake-up to the server, in one write."""
        with self._send_lock:
            self._write()

    def _write(self) -> None:
        if self._out:
            data, self._out = memoryview(b"".join(self._out)), []
            while data:  # a write may take part of it (a full pipe)
                data = data[os.write(self.conn.fileno(), data):]

    def aside(self, work: Callable[[], None]) -> None:
        """Do ``work`` in a thread of its own (a recorder closing: writing its files): the host's
        runs go on meanwhile. A crslab bug in it is printed, as the host's own are."""

        def guarded() -> None:
            try:
                work()
            except (BrokenPipeError, EOFError, OSError):
                pass  # the server went
            except Exception as exc:  # noqa: BLE001 - a crslab bug: printed, the host goes on
                import traceback

                traceback.print_exception(exc)

        self._aside = [t for t in self._aside if t.is_alive()]
        thread = threading.Thread(target=guarded, name="crslab-host-close")
        thread.start()
        self._aside.append(thread)

    def closed(self) -> None:
        """Wait for the work done aside (before the host forks: no other thread may run then)."""
        for thread in self._aside:
            thread.join()
        self._aside.clear()

    def simulation(self, config: RunConfig, limits: Limits) -> BoardRun:
        """A run's lab, opened as an instance of the host's worker (started now if there is none,
        or it ended); raises ``RunError`` when it cannot start."""
        if self.worker is None or not self.worker.alive:
            self.closed()  # forked now: no other thread of the host runs
            self.worker = BoardClient(share=self.share)
        return BoardRun(config, deadline_s=self.deadline_s, limits=limits, worker=self.worker)

    def arm_in(self, world: World) -> ArmPoses:
        """The arm's poses in ``world``'s scene (one per world, shared by the host's runs)."""
        key = "" if world.is_free_air else world.name
        if key not in self._arms:
            self._arms[key] = ArmPoses(None if world.is_free_air else world)
        return self._arms[key]

    def serve(self) -> None:
        """Pace the runs and carry out the server's messages until it closes the pipe."""
        self._loop = threading.get_ident()
        pipe = self._pipe
        try:
            while not self._server_gone:
                self.flush()  # what this wake-up made, before the host waits
                wait_ms = -1
                if self._arrived:
                    wait_ms = 0
                elif self.sessions:
                    wait_s = min(s.due_s for s in self.sessions.values()) - time.monotonic()
                    wait_ms = max(0, math.ceil(wait_s * 1000))
                if pipe.poll(wait_ms) or self._arrived:
                    while self._arrived:  # what came while the worker ran: in the order it came
                        self.handle(self._arrived.popleft())
                    while pipe.poll(0):
                        self.handle(self.conn.recv())
                now = time.monotonic()
                due = sorted((s for s in self.sessions.values() if s.due_s <= now + s.window_s),
                             key=lambda s: s.due_s)
                if due:
                    self.step(in_turn(due))
        except (EOFError, OSError):
            pass
        finally:
            for session in list(self.sessions.values()):
                self._guarded(session, session.close)
            self.sessions.clear()
            self.closed()
            if self.worker is not None:
                self.worker.close()

    def _server_wrote(self) -> bool:
        """While the worker runs the host's chunks: take what the server sent (it waits its turn
        in :meth:`serve`), and stop at once the run a page's ``stop`` or ``close`` is for (its board
        ends its chunk before the next tick, a call of its lab now: :meth:`SharedBlock.stop`), so
        that it holds the worker no longer; False once the server went."""
        try:
            while self._pipe.poll(0):
                msg = self.conn.recv()
                self._arrived.append(msg)
                kind, key = msg[0], msg[1]
                stopping = kind == wire.CLOSE or (kind == wire.PAGE and msg[2].get("type") == "stop")
                session = self.sessions.get(key) if stopping else None
                if session is not None and session.sim is not None:
                    session.sim.block.stop()
        except (EOFError, OSError):
            self._server_gone = True
            return False
        return True

    def handle(self, msg: tuple) -> None:
        """One message of the server's."""
        kind, key = msg[0], msg[1]
        if kind == wire.RUN:
            session = HostedSession(self, key, pickle.loads(msg[2]))  # from crslab's own session process
            if self._guarded(session, session.open):
                self.sessions[key] = session
        elif kind == wire.PAGE:
            session = self.sessions.get(key)
            if session is None:  # the run ended as the command came
                if msg[2].get("type") == "vars":
                    self.send_frame(wire.host_frame(key, wire.FORWARD, message(
                        "vars", ok=False, cmd=msg[2]["cmd"], reply="no run is going on: Run first")))
            elif not self._guarded(session, lambda: session.command(msg[2])):
                self.sessions.pop(key, None)
        elif kind == wire.CLOSE:
            session = self.sessions.pop(key, None)
            if session is not None:
                self._guarded(session, session.close)

    def step(self, due: list[HostedSession]) -> None:
        for session in due:
            session.turn = next(self._turns)
        self._step(due)

    def _step(self, due: list[HostedSession]) -> None:
        """Run each due session's next chunk (one request per worker), handing each on to its
        sinks as its reply comes (while the worker runs the next), then serve their controls."""
        targets = []
        for session in due:
            targets.append(session.next_target())
        taken: dict[int, Ending | None | Exception] = {}

        def each(i: int, reply: object) -> None:
            try:
                taken[i] = due[i].take(reply)
            except Exception as exc:  # noqa: BLE001 - handled below, once the worker is idle
                taken[i] = exc

        replies = self.run_chunks([(s.sim, t) for s, t in zip(due, targets)], each)  # type: ignore[misc]
        for i, (session, reply) in enumerate(zip(due, replies)):
            if i not in taken:  # the worker ended: no Ran came
                taken[i] = self._guarded_value(session, lambda s=session, r=reply: s.take(r))
            outcome = taken[i]
            if isinstance(outcome, Exception):
                self._failed(session, outcome)
                self.sessions.pop(session.key, None)
            elif not self._guarded(session, lambda s=session, e=outcome: s.after(e)):
                self.sessions.pop(session.key, None)

    def run_chunks(self, targets: list[tuple[BoardRun, int]],
                   each: Callable[[int, object], None] | None = None) -> list[object]:
        """Each simulation run to its tick, one request per worker: the worker's reply for each
        (the worker's :class:`~crslab.run.diagnosis.Ending` for a run whose worker ended);
        ``each(i, ran)`` as each target's reply comes."""
        replies: list[object] = [sim.board.ending for sim, _ in targets]
        by_worker: dict[int, list[int]] = {}
        for i, (sim, _) in enumerate(targets):
            if replies[i] is None:
                by_worker.setdefault(id(sim.board_client), []).append(i)
        for runs in by_worker.values():
            worker = targets[runs[0]][0].board_client
            on_reply = None if each is None else (lambda k, ran, runs=runs: each(runs[k], ran))
            pairs = [(targets[i][0].board, targets[i][1]) for i in runs]
            wake = Wake(self.conn.fileno(), self._server_wrote)
            for i, reply in zip(runs, worker.run(pairs, on_reply, wake)):
                replies[i] = reply
        return replies

    def _guarded_value(self, session: HostedSession, step: Callable[[], object]) -> object:
        """``step()``'s answer, or the exception it raised."""
        try:
            return step()
        except (BrokenPipeError, EOFError):
            raise
        except Exception as exc:  # noqa: BLE001 - a crslab bug, reported by _failed
            return exc

    def _guarded(self, session: HostedSession, step: object) -> bool:
        """``step()``'s answer; a crslab bug in it ends that session's run (one line for its page)
        and never the host's other runs."""
        try:
            return bool(step())  # type: ignore[operator]
        except (BrokenPipeError, EOFError):
            raise
        except Exception as exc:  # noqa: BLE001 - a crslab bug: one line for the page, the host goes on
            self._failed(session, exc)
            return False

    def _failed(self, session: HostedSession, exc: Exception) -> None:
        import traceback

        traceback.print_exception(exc)
        try:
            session.close()
        except Exception:  # noqa: BLE001
            pass
        failed = wire.ended(RunStatus.CRASHED, f"crslab failed: {type(exc).__name__}: {exc}")
        session.send(failed, wire.RUN_ENDED)


def in_turn(due: list[HostedSession]) -> list[HostedSession]:
    """What one wake-up runs of the ``due`` sessions: every one on its pace first (a page at real
    time, x its speed), then one that runs in the background (as fast as possible, or slowed: it
    costs more than its pace), the one whose turn was longest ago. A run on its pace then waits at
    most for one other run's share of the worker (the background chunk running as it fell due),
    however many runs go as fast as they can.

    >>> from types import SimpleNamespace as S
    >>> due = [S(name="fast1", background=True, turn=3), S(name="page", background=False, turn=3),
    ...        S(name="fast2", background=True, turn=2)]
    >>> [s.name for s in in_turn(due)]  # type: ignore[arg-type]
    ['page', 'fast2']
    """
    paced = [s for s in due if not s.background]
    background = [s for s in due if s.background]
    return paced + sorted(background, key=lambda s: s.turn)[:1]


def _terminated(signum: int, frame: object) -> None:
    """SIGTERM (the server ending): unwind, so every run's instance and sinks are closed."""
    raise SystemExit(0)


def serve_host(conn: Connection) -> None:
    """The host process's body."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the server's to handle
    signal.signal(signal.SIGTERM, _terminated)
    os_support.die_with_parent()
    os_support.name_process(PROCESS_NAME)
    out = socket.socket(fileno=os.dup(conn.fileno()))
    try:  # room for a few hundred chunks: a busy server never holds every run of this host back
        out.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SEND_BUFFER_BYTES)
    finally:
        out.close()
    host = RunHost(conn)
    host.worker = BoardClient(share=host.share)  # ready before the first run comes
    # what crslab's import made lives as long as the host: out of the collector's way, so that a full
    # collection scans only the runs' own objects (one of all of them held every run some ms)
    gc.freeze()
    host.serve()


