"""What ``crslab sim`` tells the user on stderr around the lab's own output, so that a first run
explains itself: before the first tick, one short paragraph (which lab, which scenario, what the
printed columns are when the lab is one of crslab's own); during the run, each scenario event
as the simulation reaches it (``t = 5.0 s: hand to ...``), an expectation with how it went
(``t = 6.0 s: expect the motor board off: met``). ``--quiet`` turns both off.

None of it goes to stdout or into the transcript: what the board prints stays exactly what the
board prints. An event is announced when the simulation has reached its tick, after everything
printed before that tick was flushed to stdout, so on a terminal it sits between the lines
printed before it and after it, at the event's simulated time at any ``--speed``.
"""

from __future__ import annotations

import sys
import textwrap
from collections.abc import Sequence
from pathlib import Path
from typing import TextIO

from crslab import resources
from crslab.scenario.event import Event
from crslab.scenario.expect_events import Expect, ExpectOutcome
from crslab.sim.running import RunningLab
from crslab.sinks.sink import Sink

PREFIX = "crslab sim: "
WIDTH = 100

OWN_LABS = {
    "lab1_kinematics.c": "crslab's own Lab 1 prints three lines twice a second: the motor angles theta1 "
    "theta2 theta3 (deg); the end effector's x y z (in) from forward kinematics; the motor angles (deg) "
    "inverse kinematics finds for that x y z (the first line again).",
    "lab2_tracking.c": "crslab's own tracking lab prints one line twice a second: the desired motor angles, "
    "the measured ones and their difference (deg).",
    "lab2_square_pid.c": "crslab's calibration lab (the controller of the real recording the arm was fitted "
    "to) steps every joint between 0 and pi/6 rad each second and prints twice a second: the three "
    "references, then the three motor angles (rad).",
}
"""What crslab's own lab files print, by file name (csrc/labs/)."""


def own_lab_note(source: Path) -> str | None:
    """What the columns are, when ``source`` is one of crslab's own labs (not a copy of one).

    >>> own_lab_note(resources.path("csrc", "labs", "lab1_kinematics.c")).split(":")[0]
    "crslab's own Lab 1 prints three lines twice a second"
    >>> own_lab_note(Path("mylab.c")) is None
    True
    """
    for name, note in OWN_LABS.items():
        own = resources.path("csrc", "labs", name)
        if Path(source).resolve() == own.resolve():
            return note
    return None


def seconds(tick: int) -> str:
    """Simulated time for messages: tenths unless the tick needs milliseconds.

    >>> seconds(5000), seconds(4583)
    ('5.0', '4.583')
    """
    return f"{tick / 1000:.1f}" if tick % 100 == 0 else f"{tick / 1000:.3f}"


def pace_text(speed: float | None) -> str:
    """How fast the run goes, in words.

    >>> pace_text(None), pace_text(1.0), pace_text(2.5)
    ('as fast as it can', 'at real time', 'at 2.5x real time')
    """
    if speed is None:
        return "as fast as it can"
    return "at real time" if speed == 1.0 else f"at {speed:g}x real time"


def introduction(*, lab: Path, scenario_name: str, scenario_description: str, end_tick: int,
                 startup_ticks: int, speed: float | None, console: bool,
                 waypoints: Path | None = None) -> str:
    """The paragraph printed before the first tick (lines end in newlines).

    >>> print(introduction(lab=Path("mylab.c"), scenario_name="hands_off", scenario_description="",
    ...                    end_tick=30000, startup_ticks=4100, speed=None, console=False), end="")
    crslab sim: mylab.c on scenario hands_off for 30.0 s, as fast as it can.
      The framework calls lab() every 1 ms from t = 4.1 s; what the lab prints follows on stdout
      exactly as Tera Term shows it. Scenario events are announced here as they happen (--quiet: no
      notes).
    """
    head = f"{PREFIX}{lab.name} on scenario {scenario_name} for {seconds(end_tick)} s, {pace_text(speed)}."
    if waypoints is not None:
        head = f"{PREFIX}{lab.name} following {waypoints.name} for {seconds(end_tick)} s, {pace_text(speed)}."
    parts = []
    if scenario_description and waypoints is None:
        parts.append(f"{scenario_name}: {scenario_description}.")
    start = f"from t = {seconds(startup_ticks)} s" if startup_ticks else "from the first tick"
    note = own_lab_note(lab)
    if note is None:
        parts.append(f"The framework calls lab() every 1 ms {start}; what the lab prints follows on stdout "
                     "exactly as Tera Term shows it.")
    else:
        parts.append(f"The framework calls lab() every 1 ms {start}. {note}")
    if console:
        parts.append("Type list, get NAME or set NAME VALUE to see and change its watched variables.")
    parts.append("Scenario events are announced here as they happen (--quiet: no notes).")
    body = textwrap.fill(" ".join(parts), WIDTH, initial_indent="  ", subsequent_indent="  ")
    return f"{head}\n{body}\n"


def announcement(event: Event, outcome: ExpectOutcome | None = None, prefix: str = PREFIX) -> str:
    """One event as announced when the run reaches it, in the event's own description; an
    expectation with how it went (``outcome``), one line per failed condition.

    >>> from crslab.scenario.hand_events import HandRelease
    >>> announcement(HandRelease(tick=23000))
    'crslab sim: t = 23.0 s: release'
    >>> from crslab.scenario.expect_events import BoardOff
    >>> off = Expect(tick=6000, conditions=(BoardOff(True),))
    >>> announcement(off, ExpectOutcome(6000, "cut.toml:9", "the motor board off"))
    'crslab sim: t = 6.0 s: expect the motor board off: met'
    >>> failed = ExpectOutcome(6000, "cut.toml:9", "", "", ("expected the motor board off, it was on",))
    >>> announcement(off, failed)
    'crslab sim: t = 6.0 s: expectation failed: expected the motor board off, it was on (cut.toml:9)'
    """
    at = f"{prefix}t = {seconds(event.tick)} s: "
    if outcome is None:
        return at + event.describe()
    if not outcome.failures:
        return f"{at}{event.describe()}: met"
    tail = f": {outcome.message}" if outcome.message else ""
    return "\n".join(f"{at}expectation failed: {why} ({outcome.where}){tail}" for why in outcome.failures)


class Narrator(Sink):
    """Announces a run's scenario events on stderr as the run reaches them (nothing when ``quiet``).

    It is a sink placed before ``stdout`` in the run's fan-out: before bytes that left the board at
    or after an event's tick go on, the event is announced (``stdout`` flushed first, so what was
    printed before the event is out before it). It is also a live control: after each chunk
    of ticks it announces the events the run reached that no print followed yet. An expectation
    is announced with how it went once :meth:`judged` was told (the run judges a chunk's
    expectations before its sinks get its bytes), in the scenario's order.
    """

    def __init__(self, events: Sequence[Event], stdout: Sink, *, quiet: bool,
                 stream: TextIO | None = None, prefix: str = PREFIX) -> None:
        self.pending = [] if quiet else sorted(events, key=lambda e: e.tick)
        self.quiet = quiet
        self.prefix = prefix
        self.stdout = stdout
        self.stream = stream if stream is not None else sys.stderr
        self.outcomes: list[ExpectOutcome] = []
        self.expects_announced = 0
        self.notes: list[tuple[int, str]] = []
        """Lines that are said whatever ``quiet`` (the motor board's cut-outs), each at its tick."""

    def judged(self, outcome: ExpectOutcome) -> None:
        """The run judged the next of the scenario's expectations (``Simulation.run``'s
        ``on_expectation``)."""
        self.outcomes.append(outcome)

    def _announcement(self, event: Event) -> str:
        if not isinstance(event, Expect) or event.note_for is not None:
            return announcement(event, prefix=self.prefix)
        k = self.expects_announced
        self.expects_announced += 1
        return announcement(event, self.outcomes[k] if k < len(self.outcomes) else None, self.prefix)

    def say(self, text: str, *, even_quiet: bool = False) -> None:
        """Print ``text`` (one or more whole lines) on stderr, unless quiet."""
        if self.quiet and not even_quiet:
            return
        self.stdout.flush()
        self.stream.write(text if text.endswith("\n") else text + "\n")
        self.stream.flush()

    def note(self, tick: int, text: str) -> None:
        """Say ``text`` (even when quiet) once the run's output has reached ``tick``: after what
        the lab printed before it and an event of the same tick, in order with the events. The
        run reports a chunk's motor-board cut-outs before its sinks get the chunk's bytes."""
        self.notes.append((tick, text))

    def reached(self, tick: int) -> None:
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

    def close(self) -> None:
        """The run is over: the notes not yet said (a run that ended early)."""
        self.reached(self.notes[-1][0] if self.notes else -1)

    def on_serial(self, tick: int, data: bytes) -> None:
        self.reached(tick)

    def serve(self, lab: RunningLab) -> None:
        """After a chunk of ticks: announce what the run reached."""
        self.reached(lab.tick)
