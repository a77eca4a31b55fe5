"""A worker many runs share (crslab/worker/share.py, csrc/board/firmware_wasm*.c): no run holds it
long, whatever its lab does. A run's chunk ends at its share of the worker's time and goes on
later where it was, printing what it prints alone; one call may cost the share's instructions and
not one more, what the board walks for it (a writev's iovecs) included; a call running past the
share's time ends its run, and a call of a run whose page pressed Stop ends at once, long before
any deadline. Ordering and instruction counts only: the times themselves are ``tools/bench.py
fair``'s."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest
from waiting import join, wait_until

from crslab._bindings import constants
from crslab.run.api import simulate
from crslab.run.assemble import make_config
from crslab.run.board_client import BoardClient
from crslab.run.diagnosis import Ending
from crslab.run.firmware_trap import diagnose
from crslab.run.status import RunStatus
from crslab.worker.share import HOST_SHARE, Share

SHARING = Path(__file__).resolve().parent / "labs" / "sharing"
SLOW = SHARING / "slow_every_call.c"
IOVECS = SHARING / "iovec_flood.c"
SPINS = SHARING / "spins_in_lab.c"
NO_TIME_LIMITS = Share(chunk_s=60.0, call_s=60.0, call_instructions=HOST_SHARE.call_instructions)
"""The host's instructions per call, and no limit in time a test could reach."""


def variant(tmp_path: Path, lab: Path, old: str, new: str) -> Path:
    """``lab`` with ``old`` replaced by ``new``, written to ``tmp_path`` under its own name."""
    text = lab.read_text()
    assert old in text
    path = tmp_path / lab.name
    path.write_text(text.replace(old, new))
    return path


def run_to(worker: BoardClient, handle: object, tick: int) -> list:
    """Run ``handle`` chunk after chunk until it reaches ``tick`` or stops otherwise: every reply."""
    replies = []
    while handle.tick < tick:  # type: ignore[attr-defined]
        ran = worker.run([(handle, tick)])[0]  # type: ignore[list-item]
        replies.append(ran)
        if isinstance(ran, Ending) or ran.code not in (0, 1, constants.CRS_RUN_CUT):
            break
    return replies


def test_a_chunk_ends_at_its_share_and_the_run_goes_on_where_it_was():
    c = constants
    config = make_config(SLOW, "tour", startup_delay=False)
    worker = BoardClient(share=HOST_SHARE)
    printed = bytearray()
    try:
        handle = worker.open(config)
        replies = run_to(worker, handle, 2000)
        handle.block.drain(lambda t, n: None, lambda t, data: printed.extend(data))
        printed += handle.block.take_line()
        worker.release(handle)
    finally:
        worker.close()
    # some 9 million instructions a call: 2000 calls are far more than one chunk's 20 ms
    assert replies[0].code == c.CRS_RUN_CUT and 0 < replies[0].tick < 2000
    assert all(r.code in (c.CRS_RUN_CUT, c.CRS_RUN_DONE) for r in replies) and replies[-1].tick == 2000
    alone = simulate(SLOW, "tour", duration_s=2.0, startup_delay=False)
    assert alone.status == "ok" and bytes(printed) == alone.transcript


def test_one_call_may_cost_the_share_s_instructions_and_not_one_more():
    c = constants
    alone = simulate(SLOW, "tour", duration_s=0.005, startup_delay=False)
    most, at = alone.stats.lab_cost_max, alone.stats.lab_max_tick
    assert most > 1_000_000
    config = make_config(SLOW, "tour", startup_delay=False)
    outcomes = {}
    for limit in (most, most - 1):
        worker = BoardClient(share=Share(chunk_s=60.0, call_s=60.0, call_instructions=limit))
        try:
            handle = worker.open(config)
            outcomes[limit] = worker.run([(handle, 5)])[0]
        finally:
            worker.close()
    assert outcomes[most].code == c.CRS_RUN_DONE and outcomes[most].tick == 5
    over = outcomes[most - 1]
    assert over.code == c.CRS_RUN_TRAPPED and over.trap["kind"] == c.CRS_FW_TRAP_TOO_COSTLY
    assert over.trap["tick"] == at
    status, line = diagnose(over.trap, SLOW.name, deadline_s=2.0)
    assert status is RunStatus.HUNG
    assert f"lab() cost more than {most - 1:,} instructions in one call at tick {at}" in line


def test_the_board_charges_a_call_one_instruction_for_each_iovec_it_walks(tmp_path):
    """The same lab with 65,000 iovecs per writev and with none costs 65,000 instructions more per
    writev: the board's walk, which costs the lab only its call. Past the share, its run ends."""
    c = constants
    (tmp_path / "empty").mkdir()
    empty = variant(tmp_path / "empty", IOVECS, "writev(1, nothing, 65000)", "writev(1, nothing, 0)")
    cost = {}
    for lab in (IOVECS, empty):
        run = simulate(lab, "tour", duration_s=0.003, startup_delay=False)
        assert run.status == "ok", run.message
        cost[lab] = run.stats.lab_cost_max
    writes = 100  # writes_each_call
    assert cost[IOVECS] - cost[empty] == writes * 65_000
    # 1000 writes a call: 65 million instructions, past the host's 15 million: ended at its first call
    flood = variant(tmp_path, IOVECS, "long writes_each_call = 100;", "long writes_each_call = 1000;")
    worker = BoardClient(share=NO_TIME_LIMITS)
    try:
        handle = worker.open(make_config(flood, "tour", startup_delay=False))
        ran = worker.run([(handle, 1000)])[0]
    finally:
        worker.close()
    assert ran.code == c.CRS_RUN_TRAPPED and ran.trap["kind"] == c.CRS_FW_TRAP_TOO_COSTLY
    assert ran.trap["tick"] == 0


def test_a_stop_ends_the_chunk_before_its_next_tick():
    c = constants
    worker = BoardClient(share=HOST_SHARE)
    try:
        handle = worker.open(make_config(SLOW, "tour", startup_delay=False))
        first = worker.run([(handle, 3)])[0]
        handle.block.stop()
        stopped = worker.run([(handle, 2000)])[0]
    finally:
        worker.close()
    assert (first.code, first.tick) == (c.CRS_RUN_DONE, 3)
    assert (stopped.code, stopped.tick) == (c.CRS_RUN_STOPPED, 3)  # not one tick more


@pytest.mark.parametrize("how", ["stop", "share"])
def test_a_call_that_never_returns_ends_at_a_stop_or_its_share_long_before_its_deadline(how):
    """The spinning call (tick 300) ends with the stop that came while it ran (kind STOPPED), or
    with the share's time for one call (TOO_LONG), not at its 60 s deadline (INTERRUPT): only
    those two could end it first."""
    c = constants
    share = Share(chunk_s=60.0, call_s=60.0 if how == "stop" else 0.1, call_instructions=0)
    worker = BoardClient(share=share, deadline_s=60.0)
    try:
        config = make_config(SPINS, "tour", startup_delay=False)
        handle = worker.open(config, deadline_s=60.0)
        block = handle.block
        if how == "stop":
            def stop_when_spinning() -> None:
                wait_until(lambda: block.tick == 300 and block.phase == c.CRS_PHASE_LAB, "the lab spinning")
                block.stop()

            stopper = threading.Thread(target=stop_when_spinning)
            stopper.start()
        ran = worker.run([(handle, 1000)])[0]
        if how == "stop":
            join(stopper, "the stop")
    finally:
        worker.close()
    assert ran.code == c.CRS_RUN_TRAPPED and ran.trap["tick"] == 300
    kind = {"stop": c.CRS_FW_TRAP_STOPPED, "share": c.CRS_FW_TRAP_TOO_LONG}[how]
    assert ran.trap["kind"] == kind
    status, line = diagnose(ran.trap, SPINS.name, deadline_s=60.0, image=config.build.image)
    if how == "stop":
        assert (status, line) == (RunStatus.INTERRUPTED, "stopped at t = 0.300 s")
    else:
        assert status is RunStatus.HUNG
        assert line.startswith(f"{SPINS.name} is too slow for a shared server: lab() used more than 100 ms "
                               "of the server's CPU time in one call at tick 300 (t = 0.300 s); it was at "
                               f"{SPINS.name}:20 in lab()")
