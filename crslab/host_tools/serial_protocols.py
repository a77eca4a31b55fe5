"""The course's two serial protocols as a host program speaks them (docs/host-tools.md, "The
protocols byte by byte"): what ``ME446_serialread`` / ``ME446_serialwrite`` send on SerialC, and
the 16-byte packets the Simulink model exchanges on SerialB every 5 ms.

>>> read_request(0xc816, 1).hex(" ")                   # the doc's worked vector
'2a 09 32 00 00 c8 16 00 01'
>>> write_request(0xc816, 3.75).hex(" ")
'2a 0b 33 00 00 c8 16 00 00 70 40'
>>> simulink_packet([1, -3, 0, 0, 0, 0, 7]).hex(" ")
'ff 7f 01 00 fd ff 00 00 00 00 00 00 00 00 07 00'
>>> plot_values(bytes.fromhex("10270000 f0d8ffff 0a1a0000 00000000"))
(1.0, -1.0, 0.6666, 0.0)
"""

from __future__ import annotations

import struct
from collections.abc import Sequence

from crslab.framework_facts import (
    MATLAB_START,
    SIMULINK_INPUTS,
    SIMULINK_PLOTS,
    SIMULINK_SCALE,
    SIMULINK_SYNC,
)

READ, WRITE = ord("2"), ord("3")
"""The MATLAB commands every course script sends: read floats, write a float (little endian)."""
READ_REPLY = ord("3")
"""The code byte of a read's reply."""
MAX_FLOATS = 0xFFFF
"""A read asks for at most this many floats (a 16-bit count)."""
ADDRESS_MASK = 0x3FFFFF
"""The C28x's data addresses are 22 bits."""
SIMULINK_REPLY_BYTES = 4 * SIMULINK_PLOTS


def read_request(address: int, floats: int) -> bytes:
    """``*``, 9, ``2``, the 16-bit-word address big endian, the number of floats big endian."""
    if not 0 <= address <= ADDRESS_MASK:
        raise ValueError(f"address {address:#x} is not a 22-bit C28x data address")
    if not 1 <= floats <= MAX_FLOATS:
        raise ValueError(f"a read asks for 1 to {MAX_FLOATS} floats, not {floats}")
    return bytes([MATLAB_START, 9, READ]) + struct.pack(">IH", address, floats)


def write_request(address: int, value: float) -> bytes:
    """``*``, 11, ``3``, the address big endian, the value as a float little endian."""
    if not 0 <= address <= ADDRESS_MASK:
        raise ValueError(f"address {address:#x} is not a 22-bit C28x data address")
    return bytes([MATLAB_START, 11, WRITE]) + struct.pack(">I", address) + struct.pack("<f", value)


def simulink_packet(values: Sequence[int]) -> bytes:
    """FF 7F and the seven values as int16 little endian (each wrapped to 16 bits, as the model's
    cast does)."""
    if len(values) != SIMULINK_INPUTS:
        raise ValueError(f"a Simulink packet carries {SIMULINK_INPUTS} values, not {len(values)}")
    return SIMULINK_SYNC + struct.pack(f"<{SIMULINK_INPUTS}H", *(int(v) & 0xFFFF for v in values))


def plot_values(reply: bytes) -> tuple[float, ...]:
    """The four PlotVars of a 16-byte reply, as the model scales them (x 0.0001)."""
    if len(reply) != SIMULINK_REPLY_BYTES:
        raise ValueError(f"a Simulink reply is {SIMULINK_REPLY_BYTES} bytes, not {len(reply)}")
    return tuple(v / SIMULINK_SCALE for v in struct.unpack(f"<{SIMULINK_PLOTS}i", reply))
