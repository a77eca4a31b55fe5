"""The bridge between the host programs on SerialB and SerialC and the running board.

After every chunk of ticks (the worker idle), the bridge hands each port's attached programs what
left the board during the chunk, and hands the board what they sent: it reaches the board's
receiver from the next tick to run on, at the baud rate (csrc/board/host_ports.h). So a host's bytes
reach the board at a tick that depends on when they arrived in wall time, as on the real board;
everything that does not depend on the host stays deterministic, and a host that only reads
changes nothing the lab prints.

While a program is attached, chunks last at most :data:`HOST_CHUNK_MS` of wall time (at any
``--speed``), so at 1x a Simulink-style host sending every 5 ms gets each answer in time for its
next step, as on the board (one packet of latency, the model's own). A run with no program
attached keeps its long chunks.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from crslab.framework_facts import TICKS_PER_S
from crslab.host_tools.ports import HostPort
from crslab.run.host_ports import HOST_PORTS
from crslab.run.running import RunningLab

HOST_CHUNK_MS = 1
"""Wall-clock milliseconds a chunk may last while a host program is attached (x ``--speed``)."""
HOST_FAST_CHUNK_TICKS = 100
"""Ticks a chunk may last at ``--fast`` while a host program is attached."""
PENDING_LIMIT = 1 << 20
"""Bytes a host may have sent ahead of the board's receiver (which takes 11.52 per ms) before
the oldest are dropped."""


class SerialBridge:
    """Carries bytes between ``ports`` (``{"SerialB": [...], "SerialC": [...]}``) and the board;
    ``status(line)`` hears what a user should know (a wedged receiver, dropped replies)."""

    def __init__(self, ports: dict[str, Sequence[HostPort]], status: Callable[[str], None]) -> None:
        unknown = set(ports) - set(HOST_PORTS)
        if unknown:
            raise ValueError(f"no host port {', '.join(sorted(unknown))}; the host ports are {HOST_PORTS}")
        self.ports = {name: list(ports.get(name, ())) for name in HOST_PORTS}
        self.status = status
        self._pending = {name: b"" for name in HOST_PORTS}
        self._wedged_told = False
        self._dropped_told = {name: 0 for name in HOST_PORTS}
        self.received = {name: 0 for name in HOST_PORTS}
        """Bytes the host programs sent on each port so far."""
        self.dropped_pending = 0

    def attached(self) -> bool:
        """Whether any host program has a port open."""
        return any(p.attached() for ports in self.ports.values() for p in ports)

    def chunk_ticks(self, speed: float | None) -> int | None:
        """Short chunks while a program is attached (see the module)."""
        if not self.attached():
            return None
        return HOST_FAST_CHUNK_TICKS if speed is None else max(1, int(HOST_CHUNK_MS * speed))

    def serve(self, lab: RunningLab) -> None:
        """Exchange each port's bytes with the board (between chunks)."""
        for name, ports in self.ports.items():
            if not ports:
                continue
            sent_now = b"".join(p.read() for p in ports)
            self.received[name] += len(sent_now)
            incoming = self._pending[name] + sent_now
            if len(incoming) > PENDING_LIMIT:
                self.dropped_pending += len(incoming) - PENDING_LIMIT
                incoming = incoming[-PENDING_LIMIT:]
            result = lab.exchange(name, incoming)
            self._pending[name] = incoming[result.taken:]
            if result.sent:
                for p in ports:
                    p.write(result.sent)
            self._report(name, result.wedged_tick, result.tx_dropped, result.tx_first_drop_tick)

    def _report(self, name: str, wedged_tick: int | None, dropped: int, first_drop_tick: int) -> None:
        if wedged_tick is not None and not self._wedged_told:
            self._wedged_told = True
            self.status(f"warning: {name}'s MATLAB receiver took a length byte of 0 or 1 at tick "
                        f"{wedged_tick} (t = {wedged_tick / TICKS_PER_S:.3f} s): the board's count never "
                        f"matches it, so {name} answers nothing more until the run is restarted, as on the "
                        f"real board")
        if dropped > self._dropped_told[name]:
            if self._dropped_told[name] == 0:
                self.status(f"warning: {name}'s reply did not fit the board's transmit ring: {dropped} bytes "
                            f"dropped as on the real board (the first at tick {first_drop_tick}); a host "
                            "waiting for them times out")
            self._dropped_told[name] = dropped

    def close(self) -> None:
        """Close every port (their symlinks go too)."""
        for ports in self.ports.values():
            for p in ports:
                p.close()
