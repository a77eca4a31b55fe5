"""Run a lab with no worker process and no lab() timing: only for measuring what isolation
and timing cost (tools/benchmarks) and for checking that they change nothing (tests). A crash
here takes the calling process down; `crslab sim` never uses this."""

from __future__ import annotations

import dataclasses
import tempfile
from pathlib import Path

from crslab.cache import read_sealed, write_sealed
from crslab.run.shared_block import SharedBlock
from crslab.worker.config import RunConfig


class InProcessRun:
    """The worker's plant, board and lab, set up in this process."""

    def __init__(self, config: RunConfig) -> None:
        from crslab.worker.board import Board

        # a native firmware from a private copy of the lab's shared object: loading the cached one
        # here would leave its globals (counters, arrays) changed for every worker this process
        # forks later (a WebAssembly firmware gets a store of its own in any case)
        self._dir = tempfile.TemporaryDirectory(prefix="crslab-inprocess-")
        if config.build.native:
            private = Path(self._dir.name) / "lab.so"
            data = read_sealed(config.build.image)
            if data is None:
                raise OSError(f"{config.build.image.name} is not what crslab built (its seal does not hold)")
            write_sealed(private, data)  # the copy sealed too: the board loads only what this user sealed
            config = dataclasses.replace(config, build=dataclasses.replace(config.build, image=private))
        # never sandboxed: the sandbox would close this very process
        config = dataclasses.replace(config, sandboxed=False)
        self.block = SharedBlock.new()
        self.worker = Board(config, self.block.memory, time_lab=False)

    def close(self) -> None:
        """Free the firmware and the shared block."""
        self.worker.close()
        self.block.close()

    def run(self, end_tick: int, chunk_ticks: int = 20_000) -> bytes:
        """Run to ``end_tick`` in chunks as ``crslab sim --fast`` does; returns the serial bytes
        (what is still on the serial line at the end included, as a run hands it on). The scope
        rows, if the run logs them, are taken and dropped after each chunk."""
        out = bytearray()
        worker = self.worker
        while worker.sim.tick < end_tick:
            worker.run(min(end_tick, worker.sim.tick + chunk_ticks))
            self.block.drain(lambda tick, chars: None, lambda tick, data: out.extend(data))
            self.block.take_log(world=False)
        return bytes(out + self.block.take_line())


def run_in_process(config: RunConfig, end_tick: int) -> bytes:
    """Run ``config`` to ``end_tick`` in this process; returns the serial bytes."""
    return InProcessRun(config).run(end_tick)
