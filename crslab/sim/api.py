"""Run a lab from Python: ``simulate(lab, scenario, ...)`` returns its transcript and signals.

>>> run = simulate(duration_s=5.0)          # the default Lab 1 on the tour, first 5 s
>>> run.result.status, run.transcript.count(b"\\n\\r")
('ok', 6)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from crslab.lab.build import build_lab
from crslab.plant.params import REST_MOTOR_RAD
from crslab.scenario.events import seconds_to_tick
from crslab.scenario.load import Scenario, check_lab, load_scenario
from crslab.sim.config import STARTUP_TICKS, SimConfig
from crslab.sim.session import DEFAULT_DEADLINE_S, NO_LIMITS, Limits, RunResult, Simulation
from crslab.sim.sinks import MemorySink, Sink

DEFAULT_REST_MOTOR_RAD = REST_MOTOR_RAD


@dataclass
class SimRun:
    """A finished run: how it ended, every serial call with its tick, and the scope log."""

    result: RunResult
    calls: list[tuple[int, bytes]]
    log: dict[str, np.ndarray] | None

    @property
    def transcript(self) -> bytes:
        """Every byte the board printed, exactly."""
        return b"".join(d for _, d in self.calls)

    def lines(self) -> list[str]:
        """The printed lines as text, without their line ends."""
        text = self.transcript.decode("latin-1").replace("\n\r", "\n").replace("\r\n", "\n")
        return text.split("\n")[:-1] if text.endswith("\n") else text.split("\n")


def make_config(
    lab: str | Path | None = None,
    scenario: str | Scenario | None = None,
    *,
    startup_delay: bool = True,
    rest_motor_rad: Sequence[float] | None = None,
    log: bool = False,
    strict: bool = False,
    budget_us: float = 1000.0,
    sanitize: bool = False,
) -> SimConfig:
    """Build the lab (cached) and load the scenario into one run's configuration.

    The arm's true resting pose is ``rest_motor_rad``, else the scenario's, else the default.
    Raises ``ScenarioError`` when the scenario writes a variable the lab does not watch.
    """
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    rest = tuple(float(v) for v in (rest_motor_rad or sc.rest_motor_rad or DEFAULT_REST_MOTOR_RAD))
    build = build_lab(Path(lab) if lab is not None else None, sanitize=sanitize)
    check_lab(sc, build)
    return SimConfig(
        build=build,
        scenario=sc,
        rest_motor_rad=rest,  # type: ignore[arg-type]
        startup_ticks=STARTUP_TICKS if startup_delay else 0,
        strict_nan=strict,
        budget_ns=int(budget_us * 1000),
        log_signals=log,
    )


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
) -> SimRun:
    """Run ``lab`` (default: crslab's Lab 1) on ``scenario`` (default: the tour).

    ``duration_s`` (simulated) overrides the scenario's end; ``speed`` None runs as fast as
    possible. Other keyword options go to :func:`make_config`.
    """
    config = make_config(lab, scenario, **options)  # type: ignore[arg-type]
    end_tick = seconds_to_tick(duration_s) if duration_s is not None else config.scenario.end_tick
    memory = MemorySink()
    every = [memory, *sinks]

    def on_serial(tick: int, data: bytes) -> None:
        for s in every:
            s.on_serial(tick, data)

    def on_log(cols: dict[str, np.ndarray]) -> None:
        for s in every:
            s.on_log(cols)

    with Simulation(config, deadline_s=deadline_s, limits=limits) as sim:
        result = sim.run(end_tick, speed=speed, on_serial=on_serial, on_log=on_log)
    return SimRun(result=result, calls=memory.calls, log=memory.log)
