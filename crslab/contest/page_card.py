"""The contest's scorecard of a run on ``crslab serve``'s page (a run with ``contest`` on), a sink of
that run (crslab/serve/run_host.py adds it; it lives here, with the judging it calls): the scope
rows the run logs (every 5th tick there, every tick when it records) kept, scored once the run ends
as ``crslab contest`` scores its run (:func:`crslab.contest.scorecard.score`), and sent to the page
as one ``scorecard`` message: the card's lines and its JSON, before the run's ``ended``."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from crslab.contest.offsets import Rest
from crslab.sinks.sink import Ended, Sink


class ContestCardSink(Sink):
    """Keeps the run's scope rows; at its end sends ``scorecard`` through ``send``."""

    def __init__(self, send: Callable[[bytes], None], world: Any, rest: Rest, startup_ticks: int,
                 budget: int) -> None:
        self.send = send
        self.world = world
        self.rest = rest
        self.startup_ticks = startup_ticks
        self.budget = budget
        self.blocks: list[dict[str, np.ndarray]] = []

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        self.blocks.append(columns)

    def on_end(self, result: Ended) -> None:
        from crslab.contest.scorecard import RunFacts, ScorecardError, score
        from crslab.run.status import RunStatus
        from crslab.sinks.page_stream import message
        from crslab.worker.run_stats import RunStats

        if not self.blocks:
            return
        log = {k: np.concatenate([b[k] for b in self.blocks]) for k in self.blocks[0]}
        self.blocks = []
        why = (result.message or "").splitlines()[0] if result.message else ""
        stats = getattr(result, "stats", None) or RunStats()
        facts = RunFacts(RunStatus(result.status), why, result.end_tick, stats, self.rest, self.startup_ticks,
                         self.budget)
        try:
            card = score(log, self.world, facts)
        except ScorecardError as exc:
            self.send(message("scorecard", lines=[f"no scorecard: {exc}"], card=None))
            return
        self.send(message("scorecard", lines=card.lines(), card=card.as_dict()))
