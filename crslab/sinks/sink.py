"""The one interface every output of a run has, and the fan-out that feeds many at once.

Everything a run reports reaches its sink, after every chunk of ticks and in this order: the
motor board's cut-outs (:meth:`Sink.on_motor_board`) and the scenario's expectations judged
(:meth:`Sink.on_expectation`) in the chunk; the print marks, each ``serial_printf``'s tick and
how many of its bytes fit the transmit ring (:meth:`Sink.on_print`; they leave in the order
printed, so a sink cuts the bytes it gets into calls by these counts); the bytes that left the
board, with the tick during whose millisecond they left (:meth:`Sink.on_serial`: the serial line
sends 11.52 characters per ms); the chunk's scope rows when the run logs them
(:meth:`Sink.on_log`); then :meth:`Sink.flush` and :meth:`Sink.on_reached` with the tick the run
reached. :meth:`Sink.on_behind` says once that the machine cannot keep the pace asked for.
:meth:`Sink.on_end` comes once when the run has ended, with how it ended (the last call of a run:
the end-of-run report is a sink's); :meth:`Sink.close` comes once at the end, also after a crash or
Ctrl-C. A sink never feeds back
into the run, so what the lab prints is the same whichever sinks watch it.

A new output of a run is one :class:`Sink` subclass that overrides what it takes; a sink that
wraps others (:class:`FanOut`, :class:`crslab.sinks.threaded.ThreadedSink`) is
:func:`forwarding`: every call of :data:`CALLS` goes to its ``forward``.

>>> from crslab.sinks.memory import MemorySink
>>> a, b = MemorySink(), MemorySink()
>>> out = FanOut([a, b])
>>> out.on_print(4100, 13); out.on_serial(4100, b"0.00 -24.06\\n\\r"); out.close()
>>> a.calls == b.calls == [(4100, b"0.00 -24.06\\n\\r")]
True
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Protocol, TypeVar

if TYPE_CHECKING:  # not imported at run time: the --rrd writer is forked before numpy is loaded
    import numpy as np

    from crslab.scenario.expect_events import ExpectOutcome

CALLS = ("on_motor_board", "on_expectation", "on_print", "on_serial", "on_log", "flush", "on_reached",
         "on_behind", "on_end")
"""Every call a run makes on its sink but :meth:`Sink.close`, in the order of a chunk (and
:meth:`Sink.on_end` once, last)."""


class Ended(Protocol):
    """How a run ended, as a sink sees it (:class:`crslab.run.status.RunResult` is one)."""

    @property
    def status(self) -> str:
        """The run's status (``ok``, ``hung``, ...)."""
        ...

    @property
    def end_tick(self) -> int:
        """The tick the run ended at."""
        ...

    @property
    def message(self) -> str:
        """Why it ended early ("" when it did not)."""
        ...


class Sink:
    """Where a run's output goes. A sink overrides what it takes; the rest do nothing."""

    def on_serial(self, tick: int, data: bytes) -> None:
        """Bytes that left the board during ``tick``'s millisecond (11.52 at most)."""

    def on_print(self, tick: int, chars: int) -> None:
        """A serial_printf during ``tick`` put ``chars`` bytes on the line (the next ones to leave
        after those of the serial_printf before it)."""

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        """Scope rows (one per tick, see :mod:`crslab.scopes.signals`) since the last call."""

    def on_motor_board(self, tick: int, joint: int, off: bool) -> None:
        """The motor board cut every output at ``tick`` (``off``; ``joint`` 1..3 was commanded
        over the limit, 0: no command came) or brought them back (``off`` False)."""

    def on_expectation(self, outcome: ExpectOutcome) -> None:
        """The next of the scenario's expectations was judged (met or failed), before the bytes
        of the chunk it was in."""

    def flush(self) -> None:
        """Make what arrived visible (terminal, disk); called after every chunk of ticks."""

    def on_reached(self, tick: int) -> None:
        """The run reached ``tick``: every event before it was applied and everything before it
        handed on; called after :meth:`flush`."""

    def on_behind(self, rate: float) -> None:
        """The machine keeps up only ``rate`` x real time, less than asked; called once."""

    def on_end(self, result: Ended) -> None:
        """The run has ended (``result``, a :class:`crslab.run.status.RunResult`): every byte was
        handed on before; called once, the run's last call before :meth:`close`."""

    def close(self) -> None:
        """Finish and release; called once, also after a crash."""


class SinkError(Exception):
    """Sinks that could not finish writing (a full disk, a removed folder): one line naming each."""


S = TypeVar("S", bound=type[Sink])


def takes(sink: Sink, name: str) -> bool:
    """Whether ``sink`` does something with the call ``name`` (:class:`Sink`'s own do nothing).

    >>> from crslab.sinks.memory import MemorySink
    >>> takes(Sink(), "on_serial"), takes(MemorySink(), "on_serial")
    (False, True)
    """
    return getattr(getattr(sink, name), "__func__", None) is not getattr(Sink, name)


def forwarding(cls: S) -> S:
    """Class decorator: each call of :data:`CALLS` the class does not define itself goes to its
    ``forward(name, args)``."""

    def forwarder(name: str) -> Callable[..., None]:
        def call(self: Sink, *args: object) -> None:
            self.forward(name, args)  # type: ignore[attr-defined]

        call.__name__ = name
        call.__doc__ = getattr(Sink, name).__doc__
        return call

    for name in CALLS:
        if name not in cls.__dict__:
            setattr(cls, name, forwarder(name))
    return cls


@forwarding
class FanOut(Sink):
    """Hands every call on to each of ``sinks``, in order."""

    def __init__(self, sinks: Iterable[Sink] = ()) -> None:
        self.sinks: list[Sink] = list(sinks)
        self._takers: dict[str, list[Callable[..., None]]] = {}
        """Per call, the sinks' methods that do something (made once per call and set of sinks)."""

    def add(self, sink: Sink) -> Sink:
        """Feed ``sink`` too (after the others); returns it."""
        self.sinks.append(sink)
        self._takers.clear()
        return sink

    def forward(self, name: str, args: tuple) -> None:
        """Call ``name`` on every sink that takes it (:class:`Sink`'s own do nothing: a run host
        hands some 400 chunks a second, each a dozen calls, to its runs' sinks).

        >>> from crslab.sinks.memory import MemorySink
        >>> out = FanOut([Sink(), MemorySink()])
        >>> out.on_serial(5, b"x"); len(out._takers["on_serial"]), out.sinks[1].sent
        (1, [(5, b'x')])
        """
        takers = self._takers.get(name)
        if takers is None:
            takers = self._takers[name] = [getattr(s, name) for s in self.sinks if takes(s, name)]
        for method in takers:
            method(*args)

    def close(self) -> None:
        """Close every sink, even when one fails; then raise :class:`SinkError` naming the files
        that could not be finished, or the first other error."""
        failed: list[OSError] = []
        other: BaseException | None = None
        sinks, self.sinks = self.sinks, []
        self._takers.clear()
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
