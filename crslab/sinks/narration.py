"""What a run tells the user on stderr around the lab's own output (``crslab sim``, ``crslab
debug``): each scenario event as the run reaches it (``t = 5.0 s: hand to ...``), an expectation
with how it went (``t = 6.0 s: expect the motor board off: met``), the motor board's cut-outs,
and a machine that cannot keep the pace asked for. ``quiet`` leaves out the events; the rest is
always said.

None of it goes to stdout or into the transcript: what the board prints stays exactly what the
board prints. An event is announced when the run has reached its tick, after everything printed
before that tick was flushed to stdout, so on a terminal it sits between the lines printed before
it and after it, at the event's simulated time at any ``--speed``.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from typing import TextIO

from crslab.framework_facts import MB_LIMIT_UNITS, MB_OVER_LIMIT_MS, MB_TIMEOUT_MS, TICKS_PER_S
from crslab.scenario.event import Event
from crslab.scenario.expect_events import Expect, ExpectOutcome
from crslab.sinks.sink import Sink


def seconds(tick: int) -> str:
    """Simulated time for messages: tenths unless the tick needs milliseconds.

    >>> seconds(5000), seconds(4583)
    ('5.0', '4.583')
    """
    return f"{tick / TICKS_PER_S:.1f}" if tick % 100 == 0 else f"{tick / TICKS_PER_S:.3f}"


def announcement(event: Event, outcome: ExpectOutcome | None = None, prefix: str = "") -> str:
    """One event as announced when the run reaches it, in the event's own description; an
    expectation with how it went (``outcome``), one line per failed condition.

    >>> from crslab.scenario.hand_events import HandRelease
    >>> announcement(HandRelease(tick=23000), prefix="crslab sim: ")
    'crslab sim: t = 23.0 s: release'
    >>> from crslab.scenario.expect_events import BoardOff
    >>> off = Expect(tick=6000, conditions=(BoardOff(True),))
    >>> announcement(off, ExpectOutcome(6000, "cut.toml:9", "the motor board off"))
    't = 6.0 s: expect the motor board off: met'
    >>> failed = ExpectOutcome(6000, "cut.toml:9", "", "", ("expected the motor board off, it was on",))
    >>> announcement(off, failed)
    't = 6.0 s: expectation failed: expected the motor board off, it was on (cut.toml:9)'
    """
    at = f"{prefix}t = {seconds(event.tick)} s: "
    if outcome is None:
        return at + event.describe()
    if not outcome.failures:
        return f"{at}{event.describe()}: met"
    tail = f": {outcome.message}" if outcome.message else ""
    return "\n".join(f"{at}expectation failed: {why} ({outcome.where}){tail}" for why in outcome.failures)


def motor_board_line(tick: int, joint: int, off: bool) -> str:
    """What is said when the motor board cuts the outputs or brings them back.

    >>> motor_board_line(4600, 1, True)
    'motor board: every output cut at tick 4600 (t = 4.600 s): joint 1 commanded beyond 4 units for 500 ms'
    >>> motor_board_line(6100, 1, False)
    'motor board: outputs back at tick 6100 (t = 6.100 s)'
    """
    at = f"at tick {tick} (t = {tick / TICKS_PER_S:.3f} s)"
    if not off:
        return f"motor board: outputs back {at}"
    why = (f"joint {joint} commanded beyond {MB_LIMIT_UNITS:g} units for {MB_OVER_LIMIT_MS} ms" if joint
           else f"no command for {MB_TIMEOUT_MS} ms")
    return f"motor board: every output cut {at}: {why}"


class NarrationSink(Sink):
    """Says a run's scenario events, expectations and motor-board cut-outs on ``stream`` (stderr),
    each line starting with ``prefix``, as the run reaches them, in the order of their ticks.

    Place it before ``stdout`` in the run's fan-out: before bytes that left the board at or after
    an event's tick go on, the event is said (``stdout`` flushed first, so what was printed before
    it is out before it); at the end of every chunk (:meth:`on_reached`) it says what the run
    reached that no print followed yet. The run reports a chunk's expectations and cut-outs before
    its bytes, so each is said with how it went, at its place.

    >>> import io
    >>> from crslab.scenario.hand_events import HandRelease
    >>> err = io.StringIO()
    >>> narration = NarrationSink([HandRelease(tick=5000)], Sink(), quiet=False, stream=err, prefix="> ")
    >>> narration.on_motor_board(4600, 0, True); narration.on_serial(4700, b"1\\n\\r")
    >>> narration.on_reached(6000); print(err.getvalue(), end="")
    > motor board: every output cut at tick 4600 (t = 4.600 s): no command for 100 ms
    > t = 5.0 s: release
    """

    def __init__(self, events: Sequence[Event], stdout: Sink, *, quiet: bool, prefix: str,
                 stream: TextIO | None = None) -> None:
        self.pending = [] if quiet else sorted(events, key=lambda e: e.tick)
        self.quiet = quiet
        self.prefix = prefix
        self.stdout = stdout
        self.stream = stream if stream is not None else sys.stderr
        self.outcomes: list[ExpectOutcome] = []
        self.expects_announced = 0
        self.notes: list[tuple[int, str]] = []
        """Lines that are said whatever ``quiet`` (the motor board's cut-outs), each at its tick."""

    def say(self, text: str, *, even_quiet: bool = False) -> None:
        """Print ``text`` (one or more whole lines) on the stream now, unless quiet."""
        if self.quiet and not even_quiet:
            return
        self.stdout.flush()
        self.stream.write(text if text.endswith("\n") else text + "\n")
        self.stream.flush()

    def _announcement(self, event: Event) -> str:
        if not isinstance(event, Expect) or event.note_for is not None:
            return announcement(event, prefix=self.prefix)
        k = self.expects_announced
        self.expects_announced += 1
        return announcement(event, self.outcomes[k] if k < len(self.outcomes) else None, self.prefix)

    def on_reached(self, tick: int) -> None:
        """The run has applied every event up to ``tick``: announce those not yet announced, and
        the notes up to ``tick``, in the order of their ticks."""
        due: list[tuple[int, int, str]] = []  # (tick, 0 event / 1 note, text)
        while self.pending and self.pending[0].tick <= tick:
            event = self.pending.pop(0)
            due.append((event.tick, 0, self._announcement(event)))
        while self.notes and self.notes[0][0] <= tick:
            at, text = self.notes.pop(0)
            due.append((at, 1, text))
        due.sort(key=lambda d: d[:2])
        lines = [text for _, kind, text in due if kind == 1 or not self.quiet]
        if lines:
            self.say("\n".join(lines), even_quiet=True)

    def on_serial(self, tick: int, data: bytes) -> None:
        self.on_reached(tick)

    def on_expectation(self, outcome: ExpectOutcome) -> None:
        self.outcomes.append(outcome)

    def on_motor_board(self, tick: int, joint: int, off: bool) -> None:
        self.notes.append((tick, self.prefix + motor_board_line(tick, joint, off)))

    def on_behind(self, rate: float) -> None:
        self.say(f"{self.prefix}this machine keeps up only {rate:.2f}x real time; running as fast as it can",
                 even_quiet=True)

    def close(self) -> None:
        """The run is over: the notes not yet said (a run that ended early)."""
        self.on_reached(self.notes[-1][0] if self.notes else -1)
