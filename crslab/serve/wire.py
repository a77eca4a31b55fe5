"""What travels between ``crslab serve``'s processes, in one place: the pipes' framing, the tags
of a page message, the run hosts' requests, and the page's ``ended`` message.

Three pipes, each a stream of frames as ``multiprocessing.Connection`` writes them (a 4-byte
big-endian length, then the bytes; a length of -1 is followed by an 8-byte one):

- **server -> session process**: the page's checked messages, pickled dicts (:func:`pickled`).
- **session process -> server**: a page message, one tag byte first (:data:`FORWARD`,
  :data:`RUN_STARTED`, :data:`RUN_ENDED`: what the server notes), or :data:`HOST_RUN` and a
  pickled :class:`~crslab.serve.run_host.HostedRun` for a run host.
- **server <-> run host**: in, pickled tuples (:data:`RUN`, key, a pickled run), (:data:`PAGE`,
  key, message), (:data:`CLOSE`, key); out, a page message for the page of session ``key``
  (:func:`host_frame`).

>>> length_prefixed(b"abc")
b'\\x00\\x00\\x00\\x03abc'
>>> host_frame("ab", FORWARD, b'{"type": "x"}')
b'\\x02abF{"type": "x"}'
>>> unhost_frame(host_frame("ab", FORWARD, b'{"type": "x"}'))
('ab', b'F', b'{"type": "x"}')
>>> ended(RunStatus.CRASHED, "the run host ended")
b'{"type": "ended", "status": "crashed", "exit_status": 3, "message": "the run host ended"}'
"""

from __future__ import annotations

import asyncio
import json
import pickle
import struct

from crslab.run.status import RunStatus

FORWARD = b"F"
"""A page message the server relays as it is."""
RUN_STARTED = b"R"
"""A page message that says a run started (``started``)."""
RUN_ENDED = b"E"
"""A page message that ends what the page asked for (a run's ``ended``, a build's ``built``, a
check's ``checked``): the page may ask for the next."""
HOST_RUN = b"H"
"""From a session process: a prepared run for a run host (not a page message)."""

RUN = "run"
"""To a run host: ``(RUN, key, pickled HostedRun)``, a run to open."""
PAGE = "page"
"""To a run host: ``(PAGE, key, message)``, a page's command for its run."""
CLOSE = "close"
"""To a run host: ``(CLOSE, key)``, the page went: its run ends now, unseen."""

_LONG = -1
"""A length that says an 8-byte one follows (a frame of 2 GB or more)."""


def length_prefixed(data: bytes) -> bytes:
    """``data`` as one frame on a pipe (what ``Connection.send_bytes`` writes)."""
    if len(data) > 0x7FFFFFFF:
        return struct.pack("!iQ", _LONG, len(data)) + data
    return struct.pack("!i", len(data)) + data


def pickled(msg: object) -> bytes:
    """``msg`` pickled, as one frame (what ``Connection.send`` writes)."""
    return length_prefixed(pickle.dumps(msg))


async def read_frame(reader: asyncio.StreamReader) -> bytes:
    """The next frame's bytes (raises ``asyncio.IncompleteReadError`` at the pipe's end)."""
    (size,) = struct.unpack("!i", await reader.readexactly(4))
    if size == _LONG:
        (size,) = struct.unpack("!Q", await reader.readexactly(8))
    return await reader.readexactly(size)


def host_frame(key: str, tag: bytes, data: bytes) -> bytes:
    """A run host's page message for the page of session ``key``: the key's length (one byte), the
    key, the tag, the message's JSON."""
    key_bytes = key.encode()
    return bytes([len(key_bytes)]) + key_bytes + tag + data


def unhost_frame(data: bytes) -> tuple[str, bytes, bytes]:
    """The key, the tag and the message of a :func:`host_frame`."""
    n = data[0]
    return data[1:1 + n].decode(), data[1 + n:2 + n], data[2 + n:]


def ended(status: RunStatus, message: str, **fields: object) -> bytes:
    """The page's ``ended`` message for a run that ended ``status`` (its exit status with it),
    ``message`` its one-line diagnosis."""
    return json.dumps({"type": "ended", "status": status.value, "exit_status": int(status.exit_status),
                       "message": message, **fields}).encode()
