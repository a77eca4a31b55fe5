"""The memory the board and the crslab process share (``crs_shared``, csrc/board/board.h), and its one
reader: what the board printed (the print marks, the bytes that left it with their ticks, what is
still on the serial line when a run ends), the scope log's rows, where the worker is (tick and
phase), what the sandbox refused, and the host ports.

The board writes the block inside a chunk of ticks; the reader takes what it holds between chunks,
when the worker is idle, and also after the worker died (the block outlives it). It is the lab's to
scribble on (a native lab shares the worker's process): every length and offset read is clamped to
the block, so nothing but the block is ever read.

>>> block = SharedBlock.new()
>>> block.drain(lambda tick, chars: None, lambda tick, data: None), block.take_line()
(0, b'')
>>> block.take_log(world=False)["enc_rad"].shape
(0, 3)
>>> block.close()
"""

from __future__ import annotations

import mmap
import os
from collections.abc import Callable
from typing import Any

import numpy as np

from crslab import os_support
from crslab._bindings import constants, read_bytes, read_ints, scope_log_columns, shared_view, size_of
from crslab.run.host_ports import PortExchange, exchange, port_index
from crslab.world.world_facts import split_world_row

TakePrint = Callable[[int, int], None]
"""``(tick, chars)``: a serial_printf during ``tick`` put ``chars`` bytes on the line."""
TakeSerial = Callable[[int, bytes], None]
"""``(tick, data)``: bytes that left the board during ``tick``'s millisecond."""


class SharedBlock:
    """One ``crs_shared`` in memory with no name in any file system (a memfd): it goes when every
    process that maps it does, however they end (killed by a grader's time limit included).
    :attr:`fd` is what a worker maps; :attr:`memory` the mapping itself."""

    def __init__(self, fd: int) -> None:
        self.fd = fd
        self.memory = mmap.mmap(fd, 0)
        self.view = shared_view(self.memory)
        self._log_columns = [
            (name, np.frombuffer(self.memory, np.dtype(kind), constants.CRS_LOG_CAPACITY * width, offset)
             .reshape(constants.CRS_LOG_CAPACITY, width))
            for name, offset, kind, width in scope_log_columns()]
        """Each scope log column over the block's whole capacity (made once: a run host takes some
        400 chunks a second)."""

    @classmethod
    def new(cls) -> SharedBlock:
        """A fresh block, zeroed."""
        return cls(os_support.anonymous_shared_file("crslab-shared", size_of("crs_shared")))

    def close(self) -> None:
        """Close the descriptor (the mapping goes with the last reference to it)."""
        if self.fd >= 0:
            os.close(self.fd)
            self.fd = -1

    # -- where the worker is -------------------------------------------------------------------
    @property
    def tick(self) -> int:
        """The tick being run, or the next to run when the worker is idle."""
        return int(self.view.tick)

    @property
    def phase(self) -> int:
        """Where the worker is (``CRS_PHASE_*``)."""
        return int(self.view.phase)

    def stop(self) -> None:
        """Ask the board to stop (a page's Stop, a page that closed): it ends its chunk before the
        next tick (``CRS_RUN_STOPPED``), a call of its firmware running now at once
        (``CRS_FW_TRAP_STOPPED``). Safe from any thread, also once the descriptor is closed (the
        mapping lasts as long as this object)."""
        self.view.stop = 1

    @property
    def refusal(self) -> Any:
        """What the sandbox refused (``crs_refusal``; ``refused`` is 0 when nothing was)."""
        return self.view.refusal

    # -- what the board printed ----------------------------------------------------------------
    def drain(self, on_print: TakePrint, on_serial: TakeSerial) -> int:
        """Hand the print marks since the last drain to ``on_print`` and the bytes that left the
        board to ``on_serial``, one call per tick that sent any; returns how many bytes could not
        be kept since then (more in one chunk than the block holds: ``CRS_SERIAL_CAPACITY`` bytes,
        ``CRS_MARK_CAPACITY`` ticks)."""
        sh = self.view
        if not (sh.print_count or sh.serial_len or sh.mark_count or sh.serial_dropped):
            return 0  # (a chunk in which the lab printed nothing: half of a page's)
        n_prints = min(int(sh.print_count), len(sh.print_tick))
        for tick, chars in zip(read_ints(sh.print_tick, n_prints), read_ints(sh.print_chars, n_prints)):
            on_print(tick, chars)
        sh.print_count = 0
        dropped = max(0, int(sh.serial_dropped))
        sh.serial_dropped = 0
        n_bytes = min(int(sh.serial_len), len(sh.serial))
        n_marks = min(int(sh.mark_count), len(sh.mark_offset))
        if n_bytes:
            raw = read_bytes(sh.serial, n_bytes)
            offsets = [min(offset, n_bytes) for offset in read_ints(sh.mark_offset, n_marks)] + [n_bytes]
            for i, tick in enumerate(read_ints(sh.mark_tick, n_marks)):
                on_serial(tick, raw[offsets[i]:max(offsets[i], offsets[i + 1])])
        sh.serial_len = 0
        sh.mark_count = 0
        return dropped

    def take_line(self) -> bytes:
        """What is still on the board's serial line (queued, not yet sent), taken off it: read
        once a run has ended, so nothing the lab printed is lost."""
        line = self.view.line
        size = size_of(line.queue)
        n, first = min(int(line.len), size), int(line.first) % size
        line.len = 0
        if not n:
            return b""
        queue = read_bytes(line.queue, size)
        return (queue[first:] + queue[:first])[:n]

    # -- the scope log -------------------------------------------------------------------------
    def take_log(self, *, world: bool) -> dict[str, np.ndarray]:
        """The scope rows the board wrote since the last call, taken off the block (its count back
        to 0): each column a ``(rows, width)`` array of its own, the world's row split into its
        quantities when the run is in a ``world`` with fixtures (else left out). Read once a chunk
        has ended, or the worker has (the rows of every tick it finished are there)."""
        sh = self.view
        n = min(max(0, int(sh.log.count)), constants.CRS_LOG_CAPACITY)
        sh.log.count = 0
        log = {name: column[:n].copy() for name, column in self._log_columns if name != "world" or world}
        if world:
            log.update(split_world_row(log.pop("world")))
        return log

    # -- the host ports ------------------------------------------------------------------------
    def exchange(self, port: str, incoming: bytes) -> PortExchange:
        """What left the board on host port ``port`` (``SerialB``, ``SerialC``) since the last
        call; ``incoming`` goes to its receiver from the next tick on (as much as its inbox takes)."""
        return exchange(self.view.host_ports[port_index(port)], incoming)
