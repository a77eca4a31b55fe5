"""The page's rows packed in C from the shared block (``crs_page_rows``, csrc/page/page_rows.c:
:meth:`BrowserStream.rows_from`, what a run host's page runs use) make the same ``chunk`` messages,
byte for byte, as the rows handed to the stream through ``on_log`` (numpy)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from crslab.run.shared_block import SharedBlock
from crslab.sinks.page_stream import BrowserStream

Chunk = tuple[np.ndarray, list[tuple[int, bytes]], bool]
"""A chunk's logged ticks, its serial bytes, and whether the run ends after it."""


class _Ended:
    def __init__(self, end_tick: int) -> None:
        self.status, self.message, self.end_tick = "ok", "", end_tick


def _fill(block: SharedBlock, ticks: np.ndarray, rng: np.random.Generator) -> None:
    """The board's rows of ``ticks`` in the block, every other value random."""
    n = len(ticks)
    for name, column in block._log_columns:
        if name == "tick":
            column[:n, 0] = ticks
        elif column.dtype.kind == "f":
            column[:n] = rng.standard_normal(column[:n].shape) * 10
        else:
            column[:n] = rng.integers(0, 2, column[:n].shape)
    block.view.log.count = n


def _messages(chunks: list[Chunk], *, world: bool, packed: bool) -> tuple[list[bytes], object, bool]:
    """The stream's messages (their ``sent`` left out) and its latest pose, as a run hands it the
    chunks (ChunkedRun.took, then ChunkedRun.ended's rows and on_end)."""
    rng = np.random.default_rng(3)
    block = SharedBlock.new()
    sent: list[bytes] = []
    stream = BrowserStream(sent.append, None, world=world)  # type: ignore[arg-type]
    if packed:
        stream.rows_from(block)
    for ticks, serial, ends in chunks:
        _fill(block, ticks, rng)
        for tick, data in serial:
            stream.on_serial(tick, data)
        if ends:  # the rows the run left: on_log only when there are some
            if not packed and len(ticks):
                stream.on_log(block.take_log(world=world))
            stream.on_end(_Ended(int(ticks[-1]) if len(ticks) else 0))  # type: ignore[arg-type]
        else:
            if not packed:
                stream.on_log(block.take_log(world=world))
            stream.on_reached(int(ticks[-1]) + 1 if len(ticks) else 0)
    block.close()
    messages = [re.sub(rb'"sent": [0-9.]+', b"", m) for m in sent]
    return messages, stream.pose.qpos_dh_rad, stream.pose.egg_broken


CASES = {
    "every 5th tick": [(np.arange(0, 250, 5), [(3, b"hi\n\r")], False), (np.arange(250, 500, 5), [], False),
                       (np.arange(500, 520, 5), [(510, b'x"\\\xe9')], True)],
    "every tick": [(np.arange(0, 250), [], False), (np.arange(250, 251), [], False),
                   (np.arange(0), [], False), (np.arange(251, 263), [], True)],
    "no rows at the end": [(np.arange(5, 20, 5), [], False), (np.arange(0), [(1, b"a")], True)],
    "a row between frames": [(np.array([15]), [], False), (np.array([20]), [], False),
                             (np.array([35]), [], True)],
}


@pytest.mark.parametrize("world", [False, True])
@pytest.mark.parametrize("case", list(CASES))
def test_packed_rows_are_the_streams_own(case: str, world: bool) -> None:
    numpy_path = _messages(CASES[case], world=world, packed=False)
    c_path = _messages(CASES[case], world=world, packed=True)
    assert c_path[0] == numpy_path[0]
    assert c_path[0] and all(m.startswith(b'{"type": "chunk"') for m in c_path[0])
    assert np.array_equal(c_path[1], numpy_path[1]) and c_path[2] == numpy_path[2]
