"""The one interface every output of a run has, and the fan-out that feeds many at once.

A run hands its sink, after every chunk of ticks: the print marks, each ``serial_printf``'s tick
and how many of its bytes fit the transmit ring (:meth:`Sink.on_print`; they leave in the order
printed, so a sink cuts the bytes it gets into calls by these counts); the bytes that left the
board, with the tick during whose millisecond they left (:meth:`Sink.on_serial`: the serial line
sends 11.52 characters per ms); then the chunk's scope rows when the run logs them
(:meth:`Sink.on_log`), then :meth:`Sink.flush`. :meth:`Sink.close` comes once at the end, also
after a crash or Ctrl-C. A sink never feeds back into the run, so what the lab prints is the same
whichever sinks watch it.

>>> from crslab.sinks.memory import MemorySink
>>> a, b = MemorySink(), MemorySink()
>>> out = FanOut([a, b])
>>> out.on_print(4100, 13); out.on_serial(4100, b"0.00 -24.06\\n\\r"); out.close()
>>> a.calls == b.calls == [(4100, b"0.00 -24.06\\n\\r")]
True
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # not imported at run time: the --rrd writer is forked before numpy is loaded
    import numpy as np


class Sink:
    """Where a run's output goes. A sink overrides what it takes; the rest do nothing."""

    def on_serial(self, tick: int, data: bytes) -> None:
        """Bytes that left the board during ``tick``'s millisecond (11.52 at most)."""

    def on_print(self, tick: int, chars: int) -> None:
        """A serial_printf during ``tick`` put ``chars`` bytes on the line (the next ones to leave
        after those of the serial_printf before it)."""

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        """Scope rows (one per tick, see :mod:`crslab.scopes.signals`) since the last call."""

    def flush(self) -> None:
        """Make what arrived visible (terminal, disk); called after every chunk of ticks."""

    def close(self) -> None:
        """Finish and release; called once, also after a crash."""


class SinkError(Exception):
    """Sinks that could not finish writing (a full disk, a removed folder): one line naming each."""


class FanOut(Sink):
    """Hands every call on to each of ``sinks``, in order."""

    def __init__(self, sinks: Iterable[Sink] = ()) -> None:
        self.sinks: list[Sink] = list(sinks)

    def add(self, sink: Sink) -> Sink:
        """Feed ``sink`` too (after the others); returns it."""
        self.sinks.append(sink)
        return sink

    def on_serial(self, tick: int, data: bytes) -> None:
        for s in self.sinks:
            s.on_serial(tick, data)

    def on_print(self, tick: int, chars: int) -> None:
        for s in self.sinks:
            s.on_print(tick, chars)

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        for s in self.sinks:
            s.on_log(columns)

    def flush(self) -> None:
        for s in self.sinks:
            s.flush()

    def close(self) -> None:
        """Close every sink, even when one fails; then raise :class:`SinkError` naming the files
        that could not be finished, or the first other error."""
        failed: list[OSError] = []
        other: BaseException | None = None
        sinks, self.sinks = self.sinks, []
        for s in sinks:
            try:
                s.close()
            except OSError as exc:
                failed.append(exc)
            except BaseException as exc:  # noqa: BLE001 - raised once every sink is closed
                other = other or exc
        if other is not None:
            raise other
        if failed:
            raise SinkError("could not finish writing "
                            + "; ".join(f"{e.filename or 'output'}: {e.strerror or e}" for e in failed))
