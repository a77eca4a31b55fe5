"""What travels between serve's processes (crslab/serve/wire.py): frames as multiprocessing writes
and reads them, the page's ``ended`` from a run's status, and a run host's page messages written
once per wake-up."""

import asyncio
import json
import os
import pickle
import select
import struct
import threading
from multiprocessing import Pipe

from crslab.run.status import RunStatus
from crslab.serve import wire
from crslab.serve.run_host import RunHost


def read_all(data: bytes) -> list[bytes]:
    async def go() -> list[bytes]:
        reader = asyncio.StreamReader()
        reader.feed_data(data)
        reader.feed_eof()
        frames = []
        try:
            while True:
                frames.append(await wire.read_frame(reader))
        except asyncio.IncompleteReadError as end:
            assert end.partial == b""  # the stream ended between two frames
        return frames

    return asyncio.run(go())


def test_frames_are_multiprocessings_both_ways():
    ours, theirs = Pipe()
    theirs.send_bytes(b"abc")
    theirs.send({"type": "run"})
    raw = os.read(ours.fileno(), 1 << 16)  # the bytes as they travel
    assert raw[:7] == wire.length_prefixed(b"abc")
    first, second = read_all(raw)
    assert first == b"abc" and pickle.loads(second) == {"type": "run"}
    theirs._send(wire.pickled(("page", "k", {"type": "stop"})))
    assert ours.recv() == ("page", "k", {"type": "stop"})


def test_a_frame_of_8_byte_length_is_read():
    assert read_all(struct.pack("!iQ", -1, 5) + b"hello" + wire.length_prefixed(b"")) == [b"hello", b""]


def test_ended_says_each_status_with_its_exit_status():
    for status in RunStatus:
        msg = json.loads(wire.ended(status, "why", end_tick=7))
        assert msg == {"type": "ended", "status": str(status), "exit_status": int(status.exit_status),
                       "message": "why", "end_tick": 7}
    assert json.loads(wire.ended(RunStatus.CRASHED, "x"))["exit_status"] == 3


def test_a_host_writes_a_wake_ups_messages_together_and_a_threads_at_once():
    ours, theirs = Pipe()
    host = RunHost(theirs)  # (its loop is this thread)
    host.send_frame(wire.host_frame("a", wire.FORWARD, b"1"))
    host.send_frame(wire.host_frame("b", wire.RUN_ENDED, b"2"))
    assert not ours.poll(0.05)  # nothing written while the wake-up goes on
    host.flush()
    assert [wire.unhost_frame(ours.recv_bytes()) for _ in range(2)] == [("a", b"F", b"1"), ("b", b"E", b"2")]
    host.flush()
    assert not ours.poll(0.05)  # each written once
    aside = threading.Thread(target=host.send_frame, args=(wire.host_frame("c", wire.RUN_ENDED, b"3"),))
    aside.start()
    aside.join()
    assert ours.poll(5) and wire.unhost_frame(ours.recv_bytes()) == ("c", b"E", b"3")


def test_a_wake_ups_first_message_waits_at_most_flush_s(monkeypatch):
    from crslab.serve import run_host

    now = [100.0]
    ours, theirs = Pipe()
    host = RunHost(theirs)

    def readable() -> bool:  # (select's own timeout: the host's clock is this test's below)
        return bool(select.select([ours], [], [], 0.05)[0])

    monkeypatch.setattr(run_host.time, "monotonic", lambda: now[0])
    host.send_frame(wire.host_frame("a", wire.FORWARD, b"1"))
    now[0] += run_host.FLUSH_S * 0.9
    host.send_frame(wire.host_frame("b", wire.FORWARD, b"2"))
    assert not readable()
    now[0] += run_host.FLUSH_S * 0.2  # the first has waited FLUSH_S: both go with the third
    host.send_frame(wire.host_frame("c", wire.FORWARD, b"3"))
    host.send_frame(wire.host_frame("d", wire.FORWARD, b"4"))  # a new wake-up's first waits again
    monkeypatch.undo()
    assert readable()
    assert [wire.unhost_frame(ours.recv_bytes())[0] for _ in range(3)] == ["a", "b", "c"]
    assert not readable()
