"""The host ports' side of the shared block, read and written by the crslab process between
chunks of ticks (the worker is idle then): what left the board on SerialB or SerialC, and what
the host sent, for the board's receiver from the next tick to run on (csrc/board/board.h,
``crs_host_port``). The block is the lab's to scribble on: every length read is clamped to it.
"""

from __future__ import annotations

from dataclasses import dataclass

from crslab._bindings import constants, read_bytes, write_bytes

HOST_PORTS = ("SerialB", "SerialC")
"""The ports a host program talks to, in the block's order (``CRS_HOST_PORT_B``, ``_C``)."""


def port_index(name: str) -> int:
    """The block's index of host port ``name``.

    >>> port_index("SerialC") == constants.CRS_HOST_PORT_C
    True
    """
    c = constants
    return {"SerialB": c.CRS_HOST_PORT_B, "SerialC": c.CRS_HOST_PORT_C}[name]


@dataclass(frozen=True)
class PortExchange:
    """One exchange with a host port between two chunks."""

    sent: bytes
    """What left the board since the last exchange."""
    taken: int
    """How many of the bytes offered the port took (offer the rest again next time)."""
    wedged_tick: int | None
    """SerialC: the tick its receiver wedged at (a length byte of 0 or 1), if it has."""
    tx_dropped: int
    """Reply bytes its transmit ring had no room for, so far."""
    tx_first_drop_tick: int


def exchange(port: object, incoming: bytes) -> PortExchange:
    """Take what left the board on ``port`` (a ``crs_host_port``) and queue ``incoming`` (as much
    as its inbox holds)."""
    c = constants
    n = min(max(0, int(port.out_len)), c.CRS_HOST_OUT_CAPACITY)  # type: ignore[attr-defined]
    sent = read_bytes(port.out, n) if n else b""  # type: ignore[attr-defined]
    port.out_len = 0  # type: ignore[attr-defined]
    waiting = min(max(0, int(port.inbox_len)), c.CRS_HOST_INBOX_CAPACITY)  # type: ignore[attr-defined]
    taken = min(len(incoming), c.CRS_HOST_INBOX_CAPACITY - waiting)
    if taken:
        write_bytes(port.inbox + waiting, incoming[:taken])  # type: ignore[attr-defined]
    port.inbox_len = waiting + taken  # type: ignore[attr-defined]
    wedged = int(port.wedged_tick) if port.wedged else None  # type: ignore[attr-defined]
    return PortExchange(sent, taken, wedged, max(0, int(port.tx_dropped)),  # type: ignore[attr-defined]
                        int(port.tx_first_drop_tick))  # type: ignore[attr-defined]
