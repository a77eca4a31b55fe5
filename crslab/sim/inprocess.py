"""Run a lab with no worker process and no lab() timing: only for measuring what isolation
and timing cost (tools/benchmarks) and for checking that they change nothing (tests). A crash
here takes the calling process down; `crslab sim` never uses this."""

from __future__ import annotations

import mmap

from crslab.sim.board_ffi import board_ffi, shared_size
from crslab.sim.config import SimConfig


def run_in_process(config: SimConfig, end_tick: int, *, chunk_ticks: int = 20_000) -> bytes:
    """Run ``config`` to ``end_tick`` in this process; returns the serial bytes."""
    from crslab.sim.worker import Worker

    shared = mmap.mmap(-1, shared_size())
    worker = Worker(config, shared)
    worker.sim.time_lab = 0
    ffi = board_ffi()
    sh = ffi.cast("crs_shared *", ffi.from_buffer(shared))
    out = bytearray()
    while worker.sim.tick < end_tick:
        worker.run(min(end_tick, worker.sim.tick + chunk_ticks))
        out += ffi.buffer(sh.serial, sh.serial_len)
        sh.serial_len = 0
        sh.mark_count = 0
    return bytes(out)
