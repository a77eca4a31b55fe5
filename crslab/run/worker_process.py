"""The worker as a process seen from the crslab process: started (forked, or spawned with the
sanitizer runtime for ``--sanitize``), asked through the pipe (:mod:`crslab.worker.worker_messages`),
watched while it works, and stopped so that it leaves no process behind. Its board instances are
:mod:`crslab.run.board_client`'s to open and run.

While a request is out, :meth:`WorkerProcess.reply` watches what the worker cannot hide: that it
is alive (else :func:`crslab.run.diagnosis.died` says why), how long a lab's current call has
run by the phase its board wrote into its shared block (a WebAssembly firmware is interrupted at
its deadline by the worker's own watchdog and the worker answers; a native worker, or a
WebAssembly one that does not answer within a grace, is killed), its CPU time by the kernel's count
(a native lab could hide that it is stuck in ``lab()``), the resident memory of a sanitized lab,
and what a native lab wrote to its standard streams (counted toward the output limit, never
shown).
"""

from __future__ import annotations

import faulthandler
import multiprocessing as mp
import os
import resource
import select
import signal
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from multiprocessing.connection import Connection
from multiprocessing.reduction import DupFd as _spawn_dup
from multiprocessing.reduction import send_handle
from pathlib import Path
from typing import Any

from crslab import os_support
from crslab._bindings import constants
from crslab.run import diagnosis
from crslab.run.diagnosis import Ending, WorkerDeath
from crslab.run.sanitizer import asan_runtime
from crslab.run.shared_block import SharedBlock
from crslab.run.status import RunStatus
from crslab.worker.config import RunConfig
from crslab.worker.debug_setup import DebugSetup
from crslab.worker.share import Share
from crslab.worker.worker_messages import End, Message, read_reply
from crslab.worker.worker_reply import Replies, UnreadableReply, read

CPU_S_PER_TICK = 1e-3
"""The CPU time a chunk may use per tick before a native worker counts as hung whatever it reports
(a native lab could hide that it is stuck in lab()): a millisecond, a slow lab's whole tick. A
WebAssembly firmware cannot write the phase the board reports, so its deadline alone holds."""
INTERRUPT_GRACE_S = 2.0
"""How long a WebAssembly worker has to answer once its firmware's call ran past its deadline (its
watchdog interrupts the call within two of its periods of it, ``CRS_WATCH_PERIOD_NS``)."""
READY_TIMEOUT_S = 60.0
SANITIZER_REPORT_ENV = "CRSLAB_SANITIZER_REPORT"
ABORT_ON_ERROR = ":abort_on_error=1"
POLL_S = 0.05
"""How often the watcher looks at the worker while it waits for a reply: a lab() or printing()
call is timed from the first look that sees its tick and phase, so a hang is found between its
deadline and a deadline plus two polls (a native call filling its memory is watched on: see
:data:`GROWING_MB`)."""
CPU_EVERY_POLLS = 20
GROWING_MB = 64
"""A native worker over its chunk's CPU allowance whose address space grew by at least this much
(MB) in the last :data:`GROWING_CPU_S` of its CPU is filling its memory, not stuck: its memory limit
will end it (a leak's page faults are CPU time, up to 3 s a GB on a virtual machine whose memory is
backed lazily), so it is watched on, and it is hung at the first such second of its CPU that finds
it grown less. Each second that lets it go on needs this much more, so a worker under a limit of L
MB gets at most L / this many. One lab() or printing() call past its wall-clock deadline is
watched on the same way, a deadline at a time: a leak's page faults on a loaded machine can take one
call of a leaking lab past a short deadline."""
GROWING_CPU_S = 1.0
"""How much of its CPU a native worker past its allowance has to grow by :data:`GROWING_MB` (s).
Counted in its CPU, not the wall clock's: a loaded machine gives it less of each second."""
DYING_S = 0.2
"""How long a worker whose memory reads 0 (being torn down: it is dying) is given to end before the
watcher decides on it (s)."""


def still_growing(grown_mb: float, memory_mb: int | None) -> bool:
    """Whether a native worker over its CPU allowance (or in a call past its deadline) is let go on:
    its address space grew by :data:`GROWING_MB` or more in its last :data:`GROWING_CPU_S` of CPU (in
    its last deadline) or, the first time, since its chunk began, and a memory limit bounds it
    (without one, nothing bounds how long it could grow).

    >>> still_growing(64.0, 2048), still_growing(63.9, 2048), still_growing(640.0, None)
    (True, False, False)
    """
    return memory_mb is not None and grown_mb >= GROWING_MB


@dataclass(frozen=True)
class Wake:
    """What else a wait for the worker answers: ``ready()`` is called when ``fd`` has something to
    read (a run host's pipe from the server: a page's Stop acts on its run's board while the worker
    runs), and returns False once ``fd`` has nothing more to give (it closed)."""

    fd: int
    ready: Callable[[], bool]


@dataclass(frozen=True)
class Limits:
    """What one run may use: worker memory and CPU time (None: no limit), printed bytes."""

    memory_mb: int | None = None
    cpu_s: float | None = None
    output_bytes: int = 16 * 1024 * 1024


NO_LIMITS = Limits()


class WorkerFd:
    """A descriptor handed to the worker. A forked worker inherits the number itself; for a spawned
    one (``--sanitize``) it is duplicated into the child while it is spawned, as multiprocessing
    passes descriptors. Never through multiprocessing's descriptor server, which would start a
    thread and a socket in the temporary folder (a path too long for a socket in a long $TMPDIR)."""

    def __init__(self, fd: int) -> None:
        self.fd = fd

    def detach(self) -> int:
        """The descriptor, now the caller's."""
        return self.fd

    def __reduce__(self) -> tuple:
        return _same, (_spawn_dup(self.fd),)  # pickled only while a child is being spawned


def _same(dup: Any) -> Any:
    return dup


def _child(conn: Connection, config: RunConfig | None, shared: WorkerFd | None, limits: Limits = NO_LIMITS,
           debug: DebugSetup | None = None, console: WorkerFd | None = None,
           deadline_s: float | None = None, share: Share | None = None) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the crslab process's to handle
    if config is not None and config.build.native:
        # a crash is diagnosed by the crslab process, not dumped here (a WebAssembly firmware's faults
        # are wasmtime's: its handlers stay as they are)
        faulthandler.disable()
    os_support.die_with_parent()  # whatever kills the crslab process
    if debug is not None:  # Ctrl-C on the terminal is the debugger's: it interrupts the lab itself
        os.setpgid(0, 0)
    if console is not None:  # a native lab's printf: counted by the crslab process, never shown
        fd = console.detach()
        os.dup2(fd, 1)
        os.dup2(fd, 2)
        os.close(fd)
    report = os.environ.pop(SANITIZER_REPORT_ENV, None)
    if report:  # the sanitizers write to stderr: keep it for the crslab process to read
        fd = os.open(report, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        os.dup2(fd, 2)
        os.close(fd)
    if limits.memory_mb is not None:
        os_support.limit_memory(limits.memory_mb * 1024 * 1024)
    if limits.cpu_s is not None:
        cpu = int(limits.cpu_s) + 1
        resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 1))
    # the worker never draws: MuJoCo's import then makes no OpenGL context (glfw, whose import loads
    # cffi's C parser: some 40-100 ms of CPU before the first lab() call); a user's MUJOCO_GL stays
    os.environ.setdefault("MUJOCO_GL", "disable")
    from crslab.worker.main import serve

    serve(conn, config, shared.detach() if shared is not None else None, debug, deadline_s, share)
    os._exit(0)


class WorkerProcess:
    """A worker, started at once; with ``config``, its instance 0 runs it on ``block`` (opened
    while the worker starts; a native worker holds only that one), else (a WebAssembly worker) it
    starts with no instance, each of those it opens taking at most ``share`` of it (None: no
    limit). See the module's text."""

    def __init__(self, config: RunConfig | None, block: SharedBlock | None, limits: Limits = NO_LIMITS,
                 debug: DebugSetup | None = None, deadline_s: float | None = None,
                 share: Share | None = None) -> None:
        self.config = config
        self.block = block
        """The shared block of instance 0 (None: a worker started with no instance)."""
        self.limits = limits
        self.debug = debug
        self.native = config is not None and config.build.native
        self.trusted = not self.native
        """A WebAssembly worker: no lab code runs in its address space, so its replies are read as
        they are (a native worker's are read as untrusted, field by field)."""
        self.lab_name = config.build.source.name if config is not None else "the worker"
        self.sanitizer_dir: str | None = None
        self._rss_limit_mb: int | None = None
        sys.stdout.flush()
        sys.stderr.flush()
        if config is not None and config.build.sanitized:
            # the sanitizer runtime must be loaded first: a fresh interpreter with it preloaded
            ctx = mp.get_context("spawn")
            self.sanitizer_dir = tempfile.mkdtemp(prefix="crslab-sanitize-")
            env = {
                os_support.PRELOAD_ENV: asan_runtime(config.build.compiler),
                # under a debugger a finding ends in abort(), where the debugger stops
                "ASAN_OPTIONS": "detect_leaks=0:halt_on_error=1" + (ABORT_ON_ERROR if debug else ""),
                "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1" + (ABORT_ON_ERROR if debug else ""),
                SANITIZER_REPORT_ENV: os.path.join(self.sanitizer_dir, "report.txt"),
            }
            # one thread, as the sandbox needs: no BLAS thread pool in the fresh interpreter
            env.update({k: "1" for k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")})
            # ASan reserves terabytes of address space: its memory is watched instead (resident)
            self._rss_limit_mb = limits.memory_mb
            limits = Limits(None, limits.cpu_s, limits.output_bytes)
        else:
            ctx = mp.get_context(os_support.WORKER_START_METHOD)
            env = {}
        self._space_limit_mb = limits.memory_mb
        """The address-space limit the worker runs under (None under ASan: its resident memory is
        watched instead, and growth of its address space says nothing)."""
        # a native lab may write to its standard streams (printf, a flood, fake progress lines): a pipe
        # the crslab process drains, counts toward the output limit and never shows (a debugged one
        # keeps the terminal); a WebAssembly firmware has no descriptor at all (the board counts)
        self._console = -1
        self._poller: Any = None  # select.poll of the pipe and the console, made once (_ready)
        self._woken = -1  # the descriptor of a Wake in the poller (-1: none)
        self.console_bytes = 0
        console = None
        if self.native and debug is None:
            self._console, console_w = os.pipe()
            os.set_blocking(self._console, False)
            console = WorkerFd(console_w)
        saved = {k: os.environ.get(k) for k in env}
        os.environ.update(env)
        try:
            self._conn, child_conn = ctx.Pipe()
            shared = WorkerFd(block.fd) if block is not None and config is not None else None
            args = (child_conn, config, shared, limits, debug, console, deadline_s, share)
            self.process = ctx.Process(target=_child, args=args, daemon=True)
            self.process.start()
        finally:
            if console is not None:
                os.close(console_w)
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
        child_conn.close()
        self._replies = Replies(self._conn.fileno())
        """The worker's replies, read off the pipe (every read of it goes through this)."""

    @property
    def pid(self) -> int:
        """The worker's process id."""
        pid = self.process.pid
        assert pid is not None
        return pid

    # -- asking --------------------------------------------------------------------------------
    def send(self, request: Message) -> None:
        """Send ``request`` (a :data:`crslab.worker.worker_messages.Request`)."""
        self._conn.send(request.wire())

    def send_block(self, block: SharedBlock) -> None:
        """Pass ``block``'s descriptor to the worker (after an ``Open``: the new instance's)."""
        send_handle(self._conn, block.fd, self.pid)

    def reply(self, *due: type[Message], deadline_s: float | None, timeout_s: float | None = None,
              during_setup: bool = False, ticks: int | None = None, instance: int | None = None,
              blocks: list[SharedBlock] | None = None, wake: Wake | None = None) -> Any:
        """The worker's next reply, checked to be one of ``due`` (about ``instance`` when given), or
        how the run ended meanwhile (an :class:`~crslab.run.diagnosis.Ending`): the worker died
        (``during_setup``: before it was ready), a lab() or printing() call of the instance of one
        of ``blocks`` (default: instance 0's) ran past ``deadline_s`` and the worker did not answer,
        the worker used more CPU time than a chunk of ``ticks`` may (:data:`CPU_S_PER_TICK` each,
        and a deadline's worth more; a native lab only), stopped answering within ``timeout_s``, or
        sent what is not a reply. ``wake``: a descriptor to answer while waiting (a run host's pipe
        from the server: a page's Stop acts while the worker runs) and what to call when it has
        something to read."""
        data = self._replies.next()
        if data is not None:  # read with the one before it (a RunMany's replies come together)
            try:
                return read_reply(read(data, self.trusted), *due, instance=instance, trusted=self.trusted)
            except UnreadableReply as exc:
                return self.tampered(str(exc))
        cpu_allowance_s = None
        if ticks is not None and deadline_s is not None and self.native:
            cpu_allowance_s = ticks * CPU_S_PER_TICK + deadline_s
        watched = blocks if blocks is not None else [b for b in (self.block,) if b is not None]
        try:
            raw = self._watch(deadline_s, timeout_s, during_setup, cpu_allowance_s, watched, wake)
            return raw if isinstance(raw, Ending) else read_reply(raw, *due, instance=instance,
                                                                  trusted=self.trusted)
        except UnreadableReply as exc:
            return self.tampered(str(exc))

    def _watch(self, deadline_s: float | None, timeout_s: float | None, during_setup: bool,
               cpu_allowance_s: float | None, blocks: list[SharedBlock], wake: Wake | None = None) -> object:
        c = constants
        start = time.monotonic()
        cpu0 = self._cpu_s() if cpu_allowance_s is not None else None
        vm_seen = self._vm_mb() if cpu_allowance_s is not None else 0.0
        cpu_seen: float | None = None  # its CPU when it was last let go on past its allowance
        # a native worker's call past its deadline is watched on while it fills its memory too: its
        # address space when it was last let go on so, or when the chunk began
        call_vm_seen = self._vm_mb() if self.native else 0.0
        # when this poll first saw the lab() or printing() call now running, per block: the tick
        # and the phase, and the wall time (the board keeps no clock of its own for it)
        call_seen: list[tuple[int, int] | None] = [None] * len(blocks)
        call_seen_at = [start] * len(blocks)
        # a native call's time leaves out what its worker waited for a core meanwhile (a loaded
        # machine's, not the lab's): its wait when the call was first seen
        call_wait_s = [0.0] * len(blocks)
        # a native worker is killed at the deadline; a WebAssembly one has its watchdog, and a
        # grace to answer after it
        allowed_s = None if deadline_s is None else deadline_s + (0.0 if self.native else INTERRUPT_GRACE_S)
        polls = 0
        pipe, replies = self._conn.fileno(), self._replies
        while True:
            try:
                # a reply already read (the next of a RunMany's, written with it) or already there is
                # taken at once
                data = replies.next()
                if data is None and self._console < 0 and pipe in self._ready(0.0, wake):
                    replies.fill()
                    data = replies.next()
                if data is not None:
                    return read(data, self.trusted)
                ready = self._ready(POLL_S, wake)
                if wake is not None and wake.fd in ready and not wake.ready():
                    wake = None  # it has nothing more to say (its pipe closed)
                if self._console in ready and self._drain_console():
                    self.kill()
                    return diagnosis.output_limit(self.lab_name, self.block.tick, self.limits.output_bytes)
                if pipe in ready:
                    replies.fill()
                    data = replies.next()
                    if data is not None:
                        return read(data, self.trusted)
            except (EOFError, ConnectionResetError):
                pass
            if not self.process.is_alive():
                self.process.join(1.0)
                death = self._death(blocks[0] if blocks else None)
                return diagnosis.not_loaded(death) if during_setup else diagnosis.died(death)
            for i, block in enumerate(blocks if allowed_s is not None else ()):
                phase = block.phase
                if phase not in (c.CRS_PHASE_LAB, c.CRS_PHASE_PRINTING):
                    continue
                call = (block.tick, phase)
                if call != call_seen[i]:
                    call_seen[i], call_seen_at[i], call_wait_s[i] = call, time.monotonic(), self._wait_s()
                past = time.monotonic() - call_seen_at[i] > allowed_s  # type: ignore[operator]
                if past and self._call_s(call_seen_at[i], call_wait_s[i]) > allowed_s:  # type: ignore[operator]
                    vm = self._vm_mb() if self.native else 0.0
                    if not (self.native and still_growing(vm - call_vm_seen, self._space_limit_mb)):
                        if self._just_died():
                            break
                        return self._hung(block, phase, deadline_s)
                    call_vm_seen, call_seen_at[i], call_wait_s[i] = vm, time.monotonic(), self._wait_s()
            over_memory = self._rss_limit_mb is not None and self._rss_mb() > self._rss_limit_mb
            if over_memory and self.block is not None:
                tick, phase = self.block.tick, self.block.phase
                self.kill()
                return diagnosis.over_memory(self.lab_name, tick, phase, self.limits.memory_mb)
            polls += 1
            if cpu0 is not None and polls % CPU_EVERY_POLLS == 0 and blocks:
                cpu = self._cpu_s()
                over = cpu is not None and cpu - cpu0 > cpu_allowance_s  # type: ignore[operator]
                if over and (cpu_seen is None or cpu - cpu_seen >= GROWING_CPU_S):  # type: ignore[operator]
                    vm = self._vm_mb()
                    if not still_growing(vm - vm_seen, self._space_limit_mb):
                        if self._just_died():
                            continue
                        return self._hung(blocks[0], c.CRS_PHASE_LAB, deadline_s)
                    vm_seen, cpu_seen = vm, cpu
            if timeout_s is not None and time.monotonic() - start > timeout_s:
                self.process.kill()
                return Ending(RunStatus.CRASHED, blocks[0].tick if blocks else 0,
                              f"{self.lab_name}: the worker stopped answering")

    def _death(self, block: SharedBlock | None) -> WorkerDeath:
        if block is None:  # a worker with no instance: a block of its own, zeroed, says nothing
            block = SharedBlock.new()
        return WorkerDeath(self.lab_name, self.process.exitcode, block, self.limits.memory_mb,
                           self.limits.cpu_s, debugged=self.debug is not None,
                           trap_fp=self.debug is not None and self.debug.trap_fp,
                           sanitizer_report=diagnosis.sanitizer_finding(self.sanitizer_dir, self.lab_name))

    def _hung(self, block: SharedBlock, phase: int, deadline_s: float | None) -> Ending:
        """The worker is killed: a lab() or printing() did not return."""
        tick = block.tick
        self.kill()
        return diagnosis.hung(self.lab_name, diagnosis.phase_function(phase), tick, deadline_s)

    def tampered(self, what: str) -> Ending:
        """The worker is killed: the lab wrote into the pipe to crslab."""
        self.kill()
        return diagnosis.tampered(self.lab_name, what, self.block.tick if self.block is not None else 0)

    def _cpu_s(self) -> float | None:
        """The worker's CPU time so far (the kernel's count, which nothing in the worker can
        change), or None when it cannot be read."""
        try:
            fields = Path(f"/proc/{self.pid}/stat").read_text().rsplit(")", 1)[1].split()
            return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
        except (OSError, IndexError, ValueError):
            return None

    def _just_died(self) -> bool:
        """Whether the worker died while a limit was being looked at: a dying worker's memory reads
        0, not grown, before it is gone (the kernel frees it first), so it is given
        :data:`DYING_S` to end, and its end (a crash at its memory limit, as a leak's is) is
        reported by the watcher's next look, not called a hang. Asked after the reading it explains."""
        if self.process.is_alive() and self._vm_mb() <= 0.0:
            self.process.join(DYING_S)
        return not self.process.is_alive()

    def _wait_s(self) -> float:
        """How long a native worker has waited for a core so far (the kernel's count of its time
        runnable but not running, s); 0 for a WebAssembly worker (its own watchdog times its calls
        on the wall clock) or when it cannot be read."""
        if not self.native:
            return 0.0
        try:
            return int(Path(f"/proc/{self.pid}/schedstat").read_text().split()[1]) / 1e9
        except (OSError, IndexError, ValueError):
            return 0.0

    def _call_s(self, seen_at: float, wait_s: float) -> float:
        """How long the call first seen at ``seen_at`` (the worker's wait then ``wait_s``) has taken,
        less the time the worker waited for a core meanwhile: on a loaded machine a native lab's
        call is not hung for the cores others took (it is for sleeping, or for spinning)."""
        return time.monotonic() - seen_at - (self._wait_s() - wait_s)

    def _vm_mb(self) -> float:
        """The worker's address space (what its memory limit bounds), MB; 0 when it cannot be read."""
        return self._statm_mb(0)

    def _rss_mb(self) -> float:
        """The worker's resident memory, MB; 0 when it cannot be read."""
        return self._statm_mb(1)

    def _statm_mb(self, field: int) -> float:
        """Field ``field`` of the worker's ``/proc/PID/statm`` (the kernel's count, in pages), MB; 0
        when it cannot be read."""
        try:
            pages = int(Path(f"/proc/{self.pid}/statm").read_text().split()[field])
        except (OSError, IndexError, ValueError):
            return 0.0
        return pages * os.sysconf("SC_PAGE_SIZE") / 2**20

    def _ready(self, timeout_s: float, wake: Wake | None = None) -> set[int]:
        """The descriptors (the pipe's, the console's, ``wake``'s) with something to read within
        ``timeout_s`` (one ``poll`` object for the worker's life: ``multiprocessing``'s ``wait``
        makes a selector on every call, a cost on every reply of a server's many)."""
        if self._poller is None:
            self._poller = select.poll()
            self._poller.register(self._conn.fileno(), select.POLLIN)
            if self._console >= 0:
                self._poller.register(self._console, select.POLLIN)
        woken = wake.fd if wake is not None else -1
        if woken != self._woken:
            if self._woken >= 0:
                self._poller.unregister(self._woken)
            if woken >= 0:
                self._poller.register(woken, select.POLLIN)
            self._woken = woken
        return {fd for fd, _ in self._poller.poll(round(timeout_s * 1000))}

    def _drain_console(self) -> bool:
        """Read (and drop) what a native lab wrote to its standard streams; True once it is more
        than the output limit."""
        while True:
            try:
                data = os.read(self._console, 1 << 20)
            except BlockingIOError:
                break
            if not data:
                break
            self.console_bytes += len(data)
        return self.console_bytes > self.limits.output_bytes

    # -- ending --------------------------------------------------------------------------------
    def kill(self) -> None:
        """End the worker now, and reap it."""
        self.process.kill()
        self.process.join()

    def close(self) -> None:
        """End the worker (it frees its instances and ends; it leaves no process behind) and remove
        the sanitizer's folder."""
        if self.process.is_alive():
            try:
                self.send(End())
            except OSError:
                pass
        self._conn.close()
        if self.process.is_alive():
            self.process.join(2.0)
            if self.process.is_alive():
                self.process.kill()
        self.process.join()
        if self._console >= 0:
            os.close(self._console)
            self._console = -1
        if self.sanitizer_dir and os.path.isdir(self.sanitizer_dir):
            for p in Path(self.sanitizer_dir).glob("*"):
                p.unlink()
            os.rmdir(self.sanitizer_dir)
