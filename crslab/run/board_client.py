"""Board instances in worker processes, seen from the crslab process: a :class:`BoardClient` starts
one worker (:mod:`crslab.run.worker_process`) and opens, runs and stops board instances in it; a
:class:`BoardHandle` is one instance (its number in the worker, its shared block, its last tick and
counters). :class:`crslab.run.board_run.BoardRun` runs one instance in a worker of its own; a
server runs many sessions as instances of a few workers (one per core).

A WebAssembly worker holds any number of instances, of any labs: they share one wasmtime engine,
one compiled module per distinct firmware and one MuJoCo model per world and plant, and a fault in
one firmware (a trap, a call past its deadline, a print that overflows the board's buffer) ends
that instance's run only (its :class:`~crslab.worker.worker_messages.Ran` says
``CRS_RUN_TRAPPED`` or another stop code); :meth:`BoardClient.run` runs many instances forward in
one request, one reply each. A native worker (``--native``, ``--sanitize``, ``crslab debug``)
holds the one instance it was started with: nothing contains its lab otherwise. When the worker
process itself ends (it died, it was killed at a deadline it did not keep, a native lab forged a
reply), every instance of it ends with the same :class:`~crslab.run.diagnosis.Ending`.

>>> from crslab.run.board_client import BoardClient  # doctest: +SKIP
>>> workers = [BoardClient() for _ in range(2)]  # doctest: +SKIP
>>> a = workers[0].open(config_a); b = workers[1].open(config_b)  # doctest: +SKIP
>>> workers[0].run([(a, 1000)])  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from crslab.run.diagnosis import Ending
from crslab.run.shared_block import SharedBlock
from crslab.run.status import RunStatus
from crslab.run.worker_process import NO_LIMITS, READY_TIMEOUT_S, Limits, Wake, WorkerProcess
from crslab.worker import worker_messages
from crslab.worker.config import RunConfig
from crslab.worker.debug_setup import DebugSetup
from crslab.worker.run_stats import RunStats
from crslab.worker.share import Share

DEFAULT_DEADLINE_S = 2.0
"""How long one call of a lab's firmware (lab(), printing(), a constructor) may run before it is
interrupted and its run ends ``hung``, by default (``--deadline``)."""

__all__ = ["DEFAULT_DEADLINE_S", "BoardHandle", "BoardClient", "InstanceNotOpened"]


class InstanceNotOpened(Exception):
    """An instance could not be opened: ``reply`` is the worker's :class:`Trapped` or
    :class:`Failed`, or the :class:`~crslab.run.diagnosis.Ending` of the worker meanwhile."""

    def __init__(self, reply: object) -> None:
        super().__init__(str(reply))
        self.reply = reply


class BoardHandle:
    """One board instance of a :class:`BoardClient`: ``id`` (its number in the worker), ``config``,
    ``block`` (its shared block: its serial bytes, its scope rows, its host ports, where it is),
    ``symbols`` (the
    lab's ``CRS_LAB_HAS_*`` bits), and, as its runs come back, ``tick`` and ``stats``. ``ending``
    is set once the worker process it lived in ended (every later request of it is refused)."""

    def __init__(self, worker: BoardClient, instance: int, config: RunConfig, block: SharedBlock,
                 deadline_s: float | None) -> None:
        self.worker = worker
        self.id = instance
        self.config = config
        self.block = block
        self.deadline_s = deadline_s
        self.symbols = 0
        self.tick = 0
        self.stats = RunStats()
        self.ending: Ending | None = None
        self.open = False

    @property
    def lab_name(self) -> str:
        """The lab file's name, as diagnoses name it."""
        return self.config.build.source.name

    def __repr__(self) -> str:
        return f"<BoardHandle {self.id} of {self.lab_name} at tick {self.tick}>"


class BoardClient:
    """A worker process and the board instances it holds (see the module's text).

    ``first``: the configuration of an instance opened while the worker starts (its handle is
    :attr:`first`; required for a native one, which holds only it); None starts a WebAssembly worker
    with no instance. ``limits`` are the worker's (its memory, its CPU time, what its labs may
    print); ``debug`` prepares it for a debugger (``crslab debug``). ``on_started()`` is called once
    the process exists, while it loads ``first``. ``share``: what each instance may take of a worker
    many runs share (:mod:`crslab.worker.share`: a server's run host); None, no limit. Raises
    :class:`InstanceNotOpened` when ``first`` cannot be opened (the worker is ended then).
    """

    def __init__(self, first: RunConfig | None = None, *, deadline_s: float | None = DEFAULT_DEADLINE_S,
                 limits: Limits = NO_LIMITS, debug: DebugSetup | None = None,
                 on_started: Callable[[], None] | None = None, share: Share | None = None) -> None:
        self.limits = limits
        self.handles: dict[int, BoardHandle] = {}
        self._next_id = 0
        self.native = first is not None and first.build.native
        block = SharedBlock.new() if first is not None else None
        self.process = WorkerProcess(first, block, limits, debug, deadline_s, share)
        self.first: BoardHandle | None = None
        if on_started is not None:
            on_started()
        if first is not None and block is not None:
            handle = self._handle(first, block, deadline_s)
            reply = self.process.reply(worker_messages.Ready, worker_messages.Failed, worker_messages.Trapped,
                                       deadline_s=deadline_s, timeout_s=READY_TIMEOUT_S, during_setup=True,
                                       instance=handle.id)
            try:
                self._opened(handle, reply)
            except InstanceNotOpened:
                self.close()
                raise
            self.first = handle

    @property
    def pid(self) -> int:
        """The worker's process id."""
        return self.process.pid

    @property
    def alive(self) -> bool:
        """Whether the worker process still runs."""
        return self.process.process.is_alive()

    def _handle(self, config: RunConfig, block: SharedBlock, deadline_s: float | None) -> BoardHandle:
        handle = BoardHandle(self, self._next_id, config, block, deadline_s)
        self._next_id += 1
        return handle

    def _opened(self, handle: BoardHandle, reply: object) -> None:
        if not isinstance(reply, worker_messages.Ready):
            handle.block.close()
            if isinstance(reply, Ending):
                self._ended(reply)
            raise InstanceNotOpened(reply)
        handle.symbols = reply.symbols
        handle.open = True
        self.handles[handle.id] = handle

    # -- instances -----------------------------------------------------------------------------
    def open(self, config: RunConfig, *, deadline_s: float | None = DEFAULT_DEADLINE_S) -> BoardHandle:
        """Open an instance running ``config`` (a WebAssembly firmware) in this worker; raises
        :class:`InstanceNotOpened` when its firmware cannot be loaded or stops in a constructor
        (the worker and its other instances go on), or the worker ended meanwhile."""
        if self.native or config.build.native:
            raise ValueError("a native firmware runs in a worker of its own (BoardClient(first=config))")
        block = SharedBlock.new()
        handle = self._handle(config, block, deadline_s)
        try:
            self.process.send(worker_messages.Open(handle.id, config, deadline_s))
            self.process.send_block(block)
        except OSError:
            block.close()
            raise InstanceNotOpened(self._worker_gone()) from None
        reply = self.process.reply(worker_messages.Ready, worker_messages.Failed, worker_messages.Trapped,
                                   deadline_s=deadline_s, timeout_s=READY_TIMEOUT_S, instance=handle.id,
                                   blocks=[block])
        self._opened(handle, reply)
        return handle

    def run(self, targets: Sequence[tuple[BoardHandle, int]],
            each: Callable[[int, worker_messages.Ran], None] | None = None,
            wake: Wake | None = None) -> list[worker_messages.Ran | Ending]:
        """Run each handle of ``targets`` to its tick, in one request: one result per target, in
        order: its :class:`~crslab.worker.worker_messages.Ran` (a faulted firmware's says how it
        stopped), or the :class:`~crslab.run.diagnosis.Ending` of the worker process when it
        ended meanwhile (then of every handle of it). ``each(i, ran)`` is called with each
        target's ``Ran`` as it comes, while the worker runs the next ones (it must not ask this
        worker anything); ``wake`` is answered while the worker runs
        (:class:`~crslab.run.worker_process.Wake`)."""
        if not targets:
            return []
        for handle, _ in targets:
            if handle.ending is not None or not handle.open:
                raise ValueError(f"{handle!r} is not open")
        if len(targets) == 1:
            handle, until = targets[0]
            request: worker_messages.Request = worker_messages.Run(handle.id, until)
        else:
            request = worker_messages.RunMany([(h.id, until) for h, until in targets])
        try:
            self.process.send(request)
        except OSError:
            ending = self._worker_gone()
            return [ending for _ in targets]
        results: list[worker_messages.Ran | Ending] = []
        deadline_s = max((h.deadline_s for h, _ in targets if h.deadline_s is not None), default=None)
        blocks = [h.block for h, _ in targets]
        for i, (handle, until) in enumerate(targets):
            reply = self.process.reply(worker_messages.Ran, deadline_s=deadline_s, ticks=until - handle.tick,
                                       instance=handle.id, blocks=blocks[i:], wake=wake)
            if isinstance(reply, Ending):
                self._ended(reply)
                results += [reply] * (len(targets) - i)
                return results
            handle.tick, handle.stats = reply.tick, reply.stats
            results.append(reply)
            if each is not None:
                each(i, reply)
        return results

    def ask(self, handle: BoardHandle, request: worker_messages.Request) -> worker_messages.Value | \
            worker_messages.Error | Ending:
        """The worker's answer to ``request`` (``Get``, ``Set``, ``Push``, ``Break`` of ``handle``)."""
        if handle.ending is not None:
            return handle.ending
        try:
            self.process.send(request)
        except OSError:
            return self._worker_gone()
        reply = self.process.reply(worker_messages.Value, worker_messages.Error, deadline_s=handle.deadline_s,
                                   blocks=[handle.block])
        if isinstance(reply, Ending):
            self._ended(reply)
        return reply

    def stop(self, handle: BoardHandle) -> worker_messages.Stopped | None:
        """Remove ``handle``'s instance from the worker: its last counters and scope rows (None when
        the worker ended before). Its shared block stays readable until :meth:`release`."""
        if not handle.open:
            return None
        handle.open = False
        self.handles.pop(handle.id, None)
        if handle.ending is not None or not self.alive:
            return None
        try:
            self.process.send(worker_messages.Stop(handle.id))
        except OSError:
            return None
        reply = self.process.reply(worker_messages.Stopped, deadline_s=handle.deadline_s, timeout_s=5.0,
                                   instance=handle.id, blocks=[handle.block])
        if isinstance(reply, Ending):
            self._ended(reply)
            return None
        handle.stats = reply.stats
        return reply

    def release(self, handle: BoardHandle) -> None:
        """Stop ``handle``'s instance (if it is open) and free its shared block."""
        self.stop(handle)
        handle.block.close()

    def kill(self) -> None:
        """End the worker now (a Ctrl-C): every instance of it ends."""
        self.process.kill()
        self._ended(Ending(RunStatus.INTERRUPTED, 0, "the worker was ended"))

    def close(self) -> None:
        """End the worker (its instances with it; it leaves no process behind). Shared blocks stay
        readable until each handle is released."""
        self.process.close()
        for handle in self.handles.values():
            handle.open = False
        self.handles.clear()

    # -- the worker ended ----------------------------------------------------------------------
    def _worker_gone(self) -> Ending:
        ending = Ending(RunStatus.CRASHED, 0, f"{self.process.lab_name}: the worker is gone")
        self._ended(ending)
        return ending

    def _ended(self, ending: Ending) -> None:
        for handle in self.handles.values():
            if handle.ending is None:
                handle.ending = ending
