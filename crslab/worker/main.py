"""The worker process: holds board instances (:class:`crslab.worker.board.Board`) and runs them on
request.

It answers the crslab process's requests (:mod:`crslab.worker.worker_messages`: open an instance,
run one or many to their ticks, get or set a watched variable, push an arm, break into the
debugger, stop an instance) until ``End`` or the pipe closes; :func:`serve` is its whole loop.

A WebAssembly worker may hold many instances: they share one wasmtime engine, one compiled module
per distinct firmware (read and hashed once: :class:`Images`), and one MuJoCo model per world and
plant among instances whose scenario never changes their model (:class:`Models`); each has its own
MuJoCo data, board, firmware store and shared block. A fault of one firmware (a trap, a hang past
its deadline, an overflowing print) ends that instance's run and leaves the others running. No lab
code runs in a WebAssembly worker's address space, so what it sends is trusted. A native worker
(``--native``, ``--sanitize``, ``crslab debug``) holds its one instance, loaded at its start, in the
run sandbox.
"""

from __future__ import annotations

import copy
import mmap
import os
import pickle
import struct
import time
from collections import OrderedDict
from multiprocessing.connection import Connection
from multiprocessing.reduction import recv_handle
from pathlib import Path

import numpy as np

from crslab._bindings import constants
from crslab.worker import worker_messages
from crslab.worker.board import Board, FirmwareStopped, ModelRefused, plant_model, trap_info
from crslab.worker.config import RunConfig
from crslab.worker.debug_setup import DebugSetup
from crslab.worker.event_effects import changes_model
from crslab.worker.share import Share
from crslab.worker.wasm_runtime import WasmImage


class Models:
    """The MuJoCo models of a worker: each world and plant compiled once, that model shared by the
    instances whose run never changes its model; one whose run does (a scenario event edits it, an
    egg breaks) gets a copy of its own (``mj_copyModel``, far cheaper than compiling the scene)."""

    def __init__(self) -> None:
        self._shared: dict[tuple, object] = {}

    def model_for(self, config: RunConfig) -> object:
        """The model an instance of ``config`` runs on."""
        key = (config.world, config.plant)
        model = self._shared.get(key)
        if model is None:
            model = self._shared[key] = plant_model(config)
        if changes_model(config.scenario.events) or config.world.egg is not None:
            return copy.copy(model)
        return model


class Images:
    """The firmware images a worker has read: the last :data:`IMAGES_KEPT` (by path, size and
    modification time), each read and hashed once while kept. A firmware's bytes are about 1 MB (its
    debug information): a worker that ran a thousand labs keeps a few, not every one."""

    def __init__(self) -> None:
        self._read: OrderedDict[tuple[Path, int, int], WasmImage] = OrderedDict()

    def image(self, path: Path) -> WasmImage:
        """The firmware at ``path``."""
        stat = path.stat()
        key = (path, stat.st_size, stat.st_mtime_ns)
        image = self._read.pop(key, None)
        if image is None:
            image = WasmImage.read(path)
        self._read[key] = image  # the newest last
        while len(self._read) > IMAGES_KEPT:
            self._read.popitem(last=False)
        return image


IMAGES_KEPT = 8
"""Firmware images a worker keeps read (:class:`Images`), as many as the compiled modules it keeps
that no instance uses (``CRS_WASM_IDLE_MODULES``): a lab run again soon is neither read nor
loaded again."""


class BoardInstances:
    """The instances of one worker process, by the number the crslab process gave each."""

    def __init__(self, share: Share | None = None) -> None:
        self.instances: dict[int, Board] = {}
        self.models = Models()
        self.images = Images()
        self.share = share
        """What each WebAssembly instance may take of this worker (None: one run has it alone)."""

    def open(self, instance: int, config: RunConfig, shared: mmap.mmap, deadline_s: float | None,
             keep_fds: list[int], debug: DebugSetup | None = None, *,
             first: bool = False) -> worker_messages.Message:
        """Open ``instance`` on the shared block ``shared`` (``first``: the instance the worker was
        started with, the only one a native firmware may be); the reply that says how it went."""
        from crslab.sandbox.run_sandbox import SandboxError

        if instance in self.instances:
            return worker_messages.Failed(instance, f"instance {instance} is already open")
        if config.build.native and (self.instances or not first):
            return worker_messages.Failed(instance, "a native firmware runs in a worker of its own, "
                                                    "started with it")
        try:
            if config.build.native:
                board = Board(config, shared, keep_fds=keep_fds, debug=debug, deadline_s=deadline_s)
            else:
                board = Board(config, shared, debug=debug, deadline_s=deadline_s,
                              model=self.models.model_for(config),
                              image=self.images.image(config.build.image), share=self.share)
        except SandboxError as exc:
            return worker_messages.Failed(instance, str(exc))
        except ModelRefused as exc:
            return worker_messages.Failed(instance, str(exc), file=exc.file)
        except FirmwareStopped as exc:
            return worker_messages.Trapped(instance, exc.trap)
        except OSError as exc:
            return worker_messages.Failed(instance, f"cannot open the lab's firmware ({exc.strerror})")
        self.instances[instance] = board
        return worker_messages.Ready(instance, int(board.sim.fw.symbols))

    def ran(self, instance: int, until_tick: int) -> worker_messages.Message:
        """Run ``instance`` to ``until_tick``: its :class:`~crslab.worker.worker_messages.Ran`."""
        board = self.instances.get(instance)
        if board is None:
            return worker_messages.Error(f"no instance {instance} is open")
        code = board.run(until_tick)
        trap = trap_info(board.c, board.sim) if code == constants.CRS_RUN_TRAPPED else None
        return worker_messages.Ran(instance, code, int(board.sim.tick), board.stats(),
                                   tuple(board.take_motor_board_events()), tuple(board.take_observations()),
                                   trap)

    def ran_wire(self, instance: int, until_tick: int) -> tuple:
        """:meth:`ran`'s reply as it travels (``Ran.wire()``); a WebAssembly instance's made straight
        from its board, its counters as a row (:meth:`~crslab.worker.run_stats.RunStats.row`: what
        a trusted reply carries), with no :class:`~crslab.worker.worker_messages.Ran` and no
        :class:`~crslab.worker.run_stats.RunStats` in between: the reply of every chunk."""
        board = self.instances.get(instance)
        if board is None or board.config.build.native:
            return self.ran(instance, until_tick).wire()
        code = board.run(until_tick)
        trap = trap_info(board.c, board.sim) if code == constants.CRS_RUN_TRAPPED else None
        events = board.take_motor_board_events()
        seen = board.take_observations()
        return ("ran", instance, code, int(board.sim.tick), board.stats_row(),
                worker_messages.plain(events) if events else (), worker_messages.plain(seen) if seen else (),
                trap)

    def answer(self, request: worker_messages.Request) -> worker_messages.Message:
        """The reply to a request about one open instance (not Open, RunMany)."""
        board = self.instances.get(getattr(request, "instance", -1))
        if board is None:
            return worker_messages.Error(f"no instance {getattr(request, 'instance', '?')} is open")
        match request:
            case worker_messages.Run(instance, until_tick):
                return self.ran(instance, until_tick)
            case worker_messages.Get(_, name):
                try:
                    return worker_messages.Value(board.get_var(name))
                except KeyError as exc:
                    return worker_messages.Error(str(exc.args[0]))
            case worker_messages.Set(_, name, index, value):
                try:
                    board.set_var(name, index, value)
                    return worker_messages.Value(None)
                except (KeyError, OverflowError) as exc:
                    return worker_messages.Error(str(exc.args[0]))
            case worker_messages.Push(_, body_forces):
                push = board.data.xfrc_applied  # MuJoCo's viewer: the mouse's force on each body
                push[:] = np.asarray(body_forces, dtype=float).reshape(push.shape)
                return worker_messages.Value(None)
            case worker_messages.Break(_):
                board.debug_break()
                return worker_messages.Value(None)
            case worker_messages.Stop(instance):
                stopped = worker_messages.Stopped(instance, board.stats())
                board.close()
                del self.instances[instance]
                return stopped
        raise TypeError(f"not a request about one instance: {request!r}")  # pragma: no cover

    def close(self) -> None:
        """Free every instance."""
        for board in self.instances.values():
            board.close()
        self.instances.clear()


class Replies:
    """A :class:`~crslab.worker.worker_messages.RunMany`'s replies, written to ``conn`` together: one
    write (and one wake-up of the crslab process) for many, not one each, once the request is done
    or its first reply has waited :data:`REPLY_WAIT_S`. Each is the frame ``conn.send`` writes.
    The hold is looked at as each reply comes: a firmware call that runs to its deadline (a hang
    the watchdog ends) holds the replies before it as long as it holds the runs after it."""

    def __init__(self, conn: Connection) -> None:
        self.conn = conn
        self.frames: list[bytes] = []
        self.since = 0.0

    def add(self, wire: tuple) -> None:
        """Hold the reply ``wire`` (as it travels: ``Message.wire()``), written now when the first
        held one has waited long enough. Pickled as ``conn.send`` would (plain data: no
        ``ForkingPickler`` needed, and its set-up costs a reply more than the pickling)."""
        data = pickle.dumps(wire, pickle.HIGHEST_PROTOCOL)
        now = time.monotonic()
        if not self.frames:
            self.since = now
        self.frames += [struct.pack("!i", len(data)) if len(data) <= 0x7FFFFFFF
                        else struct.pack("!iQ", -1, len(data)), data]
        if now - self.since >= REPLY_WAIT_S:
            self.write()

    def write(self) -> None:
        """Write the held replies, in one write (as much as the pipe takes each time)."""
        if self.frames:
            data, self.frames = memoryview(b"".join(self.frames)), []
            while data:
                data = data[os.write(self.conn.fileno(), data):]


REPLY_WAIT_S = 0.005
"""How long a RunMany's reply waits for the next ones to be written with them (s): a chunk's page
message waits for its host's wake-up anyway (crslab/serve/run_host.py's ``FLUSH_S``)."""


def serve(conn: Connection, first: RunConfig | None, shared_fd: int | None, debug: DebugSetup | None = None,
          deadline_s: float | None = None, share: Share | None = None) -> None:
    """Worker entry point: open instance 0 of ``first`` on the shared block ``shared_fd`` (when
    given), then answer requests until ``End`` or the pipe closes. ``share``: what each instance may
    take of this worker (:mod:`crslab.worker.share`; None: its one run has it alone)."""
    worker = BoardInstances(share)

    def send(reply: worker_messages.Message) -> None:
        conn.send(reply.wire())

    def mapped(fd: int) -> mmap.mmap:
        shared = mmap.mmap(fd, 0)
        os.close(fd)
        return shared

    if first is not None and shared_fd is not None:
        reply = worker.open(0, first, mapped(shared_fd), deadline_s, [conn.fileno()], debug, first=True)
        send(reply)
        if not isinstance(reply, worker_messages.Ready):
            return
    try:
        while True:
            try:
                request = worker_messages.read_request(conn.recv())
            except EOFError:
                return
            match request:
                case worker_messages.Open(instance, config, deadline):
                    send(worker.open(instance, config, mapped(recv_handle(conn)), deadline, [conn.fileno()]))
                case worker_messages.End():
                    return
                case worker_messages.RunMany(targets):
                    replies = Replies(conn)
                    for instance, until_tick in targets:
                        replies.add(worker.ran_wire(instance, until_tick))
                    replies.write()
                case worker_messages.Run(instance, until_tick):
                    conn.send(worker.ran_wire(instance, until_tick))
                case _:
                    send(worker.answer(request))
    finally:
        worker.close()
