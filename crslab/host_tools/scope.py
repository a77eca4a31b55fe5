"""A Simulink-style host on SerialB (``crslab serial scope``): every 5 ms of wall time it sends the
course model's packet (FF 7F and seven int16 values) and takes the 16-byte replies that arrived,
four PlotVars each, as the model's Packet Input does (a reply arrives during the step after its
request: one packet of latency, as in the course's model).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

from crslab.framework_facts import SIMULINK_PERIOD_MS
from crslab.host_tools.client import SerialLink
from crslab.host_tools.serial_protocols import SIMULINK_REPLY_BYTES, plot_values, simulink_packet
from crslab.scopes.rerun_stream import SIMULINK_ENTITY, SIMULINK_NAMES, open_recording

Sample = Callable[[float, tuple[float, ...]], None]
"""``(host time in s since the first packet, (PlotVar1..4))``."""


def run_scope(link: SerialLink, values: Sequence[int], on_sample: Sample, *, count: int | None = None,
              duration_s: float | None = None) -> int:
    """Exchange packets on ``link`` every 5 ms until ``count`` replies arrived or ``duration_s``
    passed (Ctrl-C stops it too); returns the number of replies."""
    packet = simulink_packet(values)
    period_s = SIMULINK_PERIOD_MS / 1000.0
    link.discard_input()
    start = time.monotonic()
    step, replies, pending = 0, 0, b""
    while (count is None or replies < count) and (duration_s is None or step * period_s < duration_s):
        due = start + step * period_s
        wait = due - time.monotonic()
        if wait > 0:
            time.sleep(wait)
        pending += link.read_available()  # the output step: what answered the last packet
        while len(pending) >= SIMULINK_REPLY_BYTES and (count is None or replies < count):
            on_sample(step * period_s, plot_values(pending[:SIMULINK_REPLY_BYTES]))
            pending = pending[SIMULINK_REPLY_BYTES:]
            replies += 1
        link.write(packet)  # the update step: the next packet
        step += 1
    return replies


class RerunScope:
    """PlotVar1..4 to the rerun viewer (``spawn``) and/or an ``.rrd`` file, on a ``host_time``
    timeline (the same entity as ``crslab sim --rerun``'s Simulink scope)."""

    ENTITY = SIMULINK_ENTITY

    def __init__(self, name: str, spawn: bool, rrd_path: str | None,
                 on_status: Callable[[str], None]) -> None:
        import rerun as rr

        self.rr = rr
        self.rec, self.active = open_recording(rr, name, spawn=spawn, rrd_path=rrd_path, on_status=on_status)
        if self.active:
            self.rec.log(self.ENTITY, rr.SeriesLines(names=SIMULINK_NAMES), static=True)

    def __call__(self, t_s: float, values: tuple[float, ...]) -> None:
        if self.active:
            self.rec.set_time("host_time", duration=t_s)
            self.rec.log(self.ENTITY, self.rr.Scalars(list(values)))

    def close(self) -> None:
        if self.active:
            self.rec.flush()
