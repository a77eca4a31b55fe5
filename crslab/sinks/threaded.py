"""A sink that does its work in a thread of its own, so the simulation does not wait for it.

The crslab process asks the worker for the next chunk of ticks only after every sink has taken
the last one. Writing a rerun recording or a CSV takes a while per chunk; in a thread, that work
overlaps the worker's next chunk. Calls reach the wrapped sink in the order they were made, only
those it takes (a CSV's sink: each chunk's rows and a flush, of a chunk's some seven calls); at
most ``depth`` of them wait, after which the simulation waits for the sink (memory stays bounded).

>>> from crslab.sinks.memory import MemorySink
>>> inner = MemorySink()
>>> sink = ThreadedSink(inner)
>>> sink.on_serial(5, b"hi\\n\\r"); sink.close()
>>> inner.sent
[(5, b'hi\\n\\r')]
"""

from __future__ import annotations

import queue
import threading

from crslab.sinks.sink import Sink, forwarding, takes

_STOP = object()


@forwarding
class ThreadedSink(Sink):
    """Hand every call to ``inner`` from a background thread (started on the first call)."""

    def __init__(self, inner: Sink, depth: int = 4) -> None:
        self.inner = inner
        self._queue: queue.Queue = queue.Queue(maxsize=depth)
        self._thread: threading.Thread | None = None
        self._error: BaseException | None = None

    def _run(self) -> None:
        while True:
            item = self._queue.get()
            if item is _STOP:
                return
            if self._error is not None:
                continue  # keep draining so the simulation never blocks on a dead sink
            method, args = item
            try:
                method(*args)
            except BaseException as exc:  # noqa: BLE001 - re-raised in close()
                self._error = exc

    def _put(self, method: object, *args: object) -> None:
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="crslab-sink", daemon=True)
            self._thread.start()
        self._queue.put((method, args))

    def forward(self, name: str, args: tuple) -> None:
        """Queue the call ``name`` for the thread (a flush too: the simulation does not wait for it),
        when the wrapped sink does something with it: a chunk makes some seven calls, and the
        queue's places are for the ones that take time (a CSV sink's rows, not its no-op calls)."""
        if takes(self.inner, name):
            self._put(getattr(self.inner, name), *args)

    def close(self) -> None:
        """Wait for the queued work, close the wrapped sink, and raise what went wrong in the thread."""
        if self._thread is not None:
            self._queue.put(_STOP)
            self._thread.join()
            self._thread = None
        error, self._error = self._error, None
        try:
            self.inner.close()
        except BaseException as exc:  # noqa: BLE001 - the first error is the one to report
            error = error or exc
        if error is not None:
            raise error
