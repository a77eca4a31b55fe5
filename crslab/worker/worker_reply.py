"""Reading the worker's replies without trusting them (a native worker's: a WebAssembly worker
runs no lab code in its address space, and its replies are read as they are).

A native worker runs the lab's code, and the lab can write anything to the pipe it shares with the
crslab process. A plain ``Connection.recv()`` unpickles, and unpickling can call any function:
a lab could run code in the crslab process, outside the sandbox. So replies are read as bytes
(bounded in size) and unpickled with only the globals a reply may hold: numpy arrays of numbers
and their dtypes (the scope log itself travels as one buffer of bytes). Everything else in a
reply (tuples, lists, dicts, strings, numbers) needs no global at all.

>>> import pickle, numpy as np
>>> decode(pickle.dumps(("ran", 0, 5, {"tick": [5]}, {"tick": np.arange(3)})))[4]["tick"]
array([0, 1, 2])
>>> decode(pickle.dumps(print))
Traceback (most recent call last):
...
crslab.worker.worker_reply.UnreadableReply: the worker's reply names builtins.print
"""

from __future__ import annotations

import io
import os
import pickle
import struct

import numpy as np

MAX_REPLY_BYTES = 256 * 1024 * 1024
"""The largest reply read (a chunk's scope log is a few MB)."""

_ALLOWED = {
    ("numpy", "dtype"), ("numpy", "ndarray"),
    ("numpy._core.numeric", "_frombuffer"), ("numpy.core.numeric", "_frombuffer"),
    ("numpy._core.multiarray", "_reconstruct"), ("numpy.core.multiarray", "_reconstruct"),
    ("numpy._core.multiarray", "scalar"), ("numpy.core.multiarray", "scalar"),
}


class UnreadableReply(Exception):
    """The worker sent something that is not a reply (the lab wrote into the pipe)."""


class _ReplyUnpickler(pickle.Unpickler):
    def find_class(self, module: str, name: str) -> object:
        if (module, name) not in _ALLOWED:
            raise UnreadableReply(f"the worker's reply names {module}.{name}")
        return super().find_class(module, name)

    def persistent_load(self, pid: object) -> object:
        raise UnreadableReply("the worker's reply holds a persistent reference")


def _check(value: object) -> None:
    if isinstance(value, np.ndarray) and value.dtype.kind not in "biuf":
        raise UnreadableReply(f"the worker's reply holds an array of {value.dtype}")
    if isinstance(value, (tuple, list)):
        for v in value:
            _check(v)
    elif isinstance(value, dict):
        for v in value.values():
            _check(v)


def decode(data: bytes) -> object:
    """A reply from its pickled bytes, refusing anything but plain data and numeric arrays."""
    try:
        value = _ReplyUnpickler(io.BytesIO(data)).load()
    except UnreadableReply:
        raise
    except Exception as exc:  # noqa: BLE001 - any malformed stream is one kind of failure
        raise UnreadableReply(f"the worker's reply cannot be read ({type(exc).__name__})") from None
    _check(value)
    return value


READ_BYTES = 1 << 20
"""The most one read of the pipe takes (:class:`Replies`)."""
_HEADER = struct.Struct("!i")
_LONG_HEADER = struct.Struct("!Q")


class Replies:
    """The worker's replies off its end of the pipe (``fd``), framed as ``Connection.send_bytes``
    frames them, every byte there taken in one read: a worker writes a request's replies together
    (crslab/worker/main.py), so a run host reads them with one system call, not two for each (its
    length, its bytes) and a poll between. :meth:`next` gives the next whole reply's bytes, or
    None until one has come (:meth:`fill` reads what came).

    >>> r, w = os.pipe()
    >>> _ = os.write(w, _HEADER.pack(2) + b"ab" + _HEADER.pack(3) + b"c")
    >>> replies = Replies(r); replies.fill(); replies.next(), replies.next()
    (b'ab', None)
    >>> _ = os.write(w, b"de"); replies.fill(); replies.next()
    b'cde'
    >>> os.close(w); replies.fill()
    Traceback (most recent call last):
    ...
    EOFError
    """

    def __init__(self, fd: int) -> None:
        self.fd = fd
        self._buffer = bytearray()
        self._at = 0

    def fill(self) -> None:
        """Read what the pipe holds (it has something: a poll said so, or this waits); raises
        ``EOFError`` when the worker's end is closed."""
        data = os.read(self.fd, READ_BYTES)
        if not data:
            raise EOFError
        if self._at:
            del self._buffer[:self._at]
            self._at = 0
        self._buffer += data

    def next(self) -> bytes | None:
        """The next whole reply's bytes (None: it has not all come); raises :class:`UnreadableReply`
        for a length no reply has."""
        buffer, at = self._buffer, self._at
        if len(buffer) - at < 4:
            return None
        (size,), start = _HEADER.unpack_from(buffer, at), at + 4
        if size == -1:
            if len(buffer) - at < 12:
                return None
            (size,), start = _LONG_HEADER.unpack_from(buffer, start), start + 8
        if size < 0 or size > MAX_REPLY_BYTES:
            raise UnreadableReply(f"the worker's reply cannot be read (a reply of {size} bytes)")
        if len(buffer) - start < size:
            return None
        self._at = start + size
        return bytes(buffer[start:self._at])


def read(data: bytes, trusted: bool = False) -> object:
    """A reply from the bytes :class:`Replies` read (raises ``UnreadableReply``). ``trusted``: a
    WebAssembly worker's (no lab code runs in its address space), unpickled as it is."""
    return pickle.loads(data) if trusted else decode(data)
