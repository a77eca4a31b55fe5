"""The server's table of page sessions, changed by threads (a session starts and ends in one, not
to hold up the event loop) while the event loop reads it: no read sees it half changed, and
``--max-sessions`` holds however many pages start at once."""

from __future__ import annotations

import itertools
import threading
from pathlib import Path

from serve_tables import start_without_processes, table_session

from crslab.serve.page_process import SessionLimits
from crslab.serve.page_sessions import LimitError, PageSession, Sessions, UserLimits


def test_sessions_starting_and_ending_in_threads_while_the_loop_admits_runs(monkeypatch, tmp_path):
    sessions = Sessions(UserLimits(compiles_per_minute=10**9, max_sessions=150, max_sessions_per_user=10**6),
                        SessionLimits())
    started = threading.Barrier(9)
    numbers = itertools.count()  # next() on a count is atomic: every session gets a number of its own

    def fake_start(user: str) -> PageSession:
        # a real start forks a process from the fork server: here, only what the table keeps (an id
        # made of id(object()) would repeat, a freed object's address being reused at once)
        return table_session(f"{user}-{next(numbers)}", user, Path(tmp_path))

    start_without_processes(monkeypatch, sessions, fake_start)
    outcomes: list[str] = []

    def page_opener(k: int) -> None:
        started.wait()
        for i in range(40):
            try:
                session = sessions.start(f"student{k}")
                outcomes.append("started")
                if i % 4 == 3:
                    sessions.close(session)
                    outcomes.append("closed")
            except LimitError:
                outcomes.append("full")

    threads = [threading.Thread(target=page_opener, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    started.wait()
    errors = []
    probe = table_session("probe", "studentX", Path(tmp_path))
    while any(t.is_alive() for t in threads):
        try:  # what the event loop does for every page message: reads the whole table
            sessions.admit(probe, {"type": "run", "scenario": {"name": "tour"}}, 0.0)
            probe.running = None
            assert len(sessions.all()) <= 150
        except RuntimeError as exc:  # "dictionary changed size during iteration"
            errors.append(exc)
    for t in threads:
        t.join()
    assert errors == []
    assert outcomes.count("full") > 0  # 320 tries, a quarter closed again: the table filled up
    open_now = outcomes.count("started") - outcomes.count("closed")
    assert open_now == len(sessions.all()) <= 150  # every start and close counted, never over
    while True:  # the places closed last are taken again, up to the limit and not one more
        try:
            sessions.start("late")
        except LimitError:
            break
    assert len(sessions.all()) == 150


def test_each_run_ends_its_chunks_at_its_own_phase_of_the_clock(monkeypatch):
    """A watching run's chunks end where the server's phase puts them in every 250 ms of the
    machine's clock (the first takes 125 to 375 ms to get there, the others 250), so runs started
    together do not all wake at once; while the page acts, chunks are 20 ms; the one pacer (the
    terminal's too) says when the next chunk is due."""
    from crslab.live.console import VarConsole
    from crslab.run import pacing
    from crslab.run.pacing import PAGE_CHUNKS, Pacer
    from crslab.serve.stream import INTERACTIVE_CHUNK_TICKS, PageControl
    from crslab.sinks.page_stream import BrowserStream

    clock = [1000.0375]  # the machine's monotonic clock, s
    monkeypatch.setattr(pacing.time, "monotonic", lambda: clock[0])

    class Lab:
        tick = 0

    for phase in (0.0, 0.3, 0.618, 0.99):
        pacer = Pacer(1.0, chunks=PAGE_CHUNKS, phase=phase)  # tick 0 is due at 1000.0375 s
        stream = BrowserStream(lambda data: None, None)  # type: ignore[arg-type]
        control = PageControl(lambda data: None, stream, VarConsole(()), pacer, lambda msg: None)
        first, _ = pacer.next_chunk(0, 25_000, [control])
        assert 125 <= first <= 375
        end_due = 1000.0375 + first / 1000.0
        assert pacer.due_s(first) == end_due
        # within half a tick of the phase (the chunk is whole ticks)
        assert abs((end_due - phase * 0.25 + 0.125) % 0.25 - 0.125) <= 0.0005
        assert pacer.next_chunk(first, 25_000, [control])[0] == first + PAGE_CHUNKS.realtime_ticks
        lab = Lab()
        lab.tick = first
        control.command(lab, {"type": "speed", "speed": 2.0})
        # the page just acted (a new speed, due from now): 20 ms x 2 of chunks, for 2 s of ticks
        assert pacer.next_chunk(first, 25_000, [control])[0] == first + 2 * INTERACTIVE_CHUNK_TICKS
        assert pacer.due_s(first + 1000) == clock[0] + 0.5
        lab.tick = first + 2000  # 2 s of ticks later: the page only watches again
        control.serve(lab)
        assert control.chunk_ticks(2.0) is None


def test_the_phases_of_many_runs_lie_evenly_over_the_period():
    """The golden ratio's multiples: however many runs go at once, no two wake-ups are much
    closer, and no gap much wider, than an even spread's (the three-gap theorem: at most three
    gap sizes, the largest under 2.7 / n)."""
    from crslab.serve.page_sessions import run_phase

    for n in (10, 50, 100, 150):
        phases = sorted(run_phase(k) for k in range(n))
        gaps = [b - a for a, b in zip(phases, phases[1:])] + [1 - phases[-1] + phases[0]]
        assert max(gaps) < 2.7 / n and min(gaps) > 0.35 / n
        assert len({round(g, 9) for g in gaps}) <= 3
