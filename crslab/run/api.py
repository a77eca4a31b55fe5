"""Run a lab from Python: ``simulate(lab, scenario, ...)`` returns its transcript and signals.

>>> run = simulate(duration_s=5.0)          # the default Lab 1 on the tour, first 5 s
>>> run.status, run.transcript.count(b"\\n\\r")
(<RunStatus.OK: 'ok'>, 6)
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from crslab.run.assemble import DEFAULT_REST_MOTOR_RAD, make_config, run_kept
from crslab.run.board_run import DEFAULT_DEADLINE_S, NO_LIMITS, Limits
from crslab.run.status import RunResult
from crslab.scenario.event import seconds_to_tick
from crslab.scenario.load import Scenario
from crslab.sinks.sink import Sink

__all__ = ["DEFAULT_REST_MOTOR_RAD", "make_config", "simulate"]


def simulate(
    lab: str | Path | None = None,
    scenario: str | Scenario | None = None,
    *,
    duration_s: float | None = None,
    speed: float | None = None,
    deadline_s: float = DEFAULT_DEADLINE_S,
    limits: Limits = NO_LIMITS,
    sinks: Sequence[Sink] = (),
    **options: object,
) -> RunResult:
    """Run ``lab`` (default: crslab's Lab 1) on ``scenario`` (default: the tour).

    ``duration_s`` (simulated) overrides the scenario's end; ``speed`` None runs as fast as
    possible. Other keyword options go to :func:`make_config`.
    """
    config = make_config(lab, scenario, **options)  # type: ignore[arg-type]
    end_tick = seconds_to_tick(duration_s) if duration_s is not None else config.scenario.end_tick
    return run_kept(config, end_tick, sinks, speed=speed, deadline_s=deadline_s, limits=limits)
