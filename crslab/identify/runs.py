"""Running a lab for the fit: the same lab, many plant parameters, each run in its own worker
(sandboxed like every run), several at once.

Each run starts at rest and calls ``lab()`` from the first tick (no startup delay: before 4.1 s the
real board sends nothing and the arm rests, so the lab's timeline is the same, 4.1 s sooner). What
the fit compares is the lab's ``Simulink_PlotVar1..4`` at every tick.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from crslab import os_support
from crslab.plant.plant_params import PlantParams
from crslab.worker.config import RunConfig


class RunFailed(RuntimeError):
    """A run of the lab ended other than normally; the message says how."""


@dataclasses.dataclass(frozen=True)
class IdentifyRun:
    """What one run needs: the prepared configuration, its plant and resting pose, and its length."""

    config: RunConfig
    plant: PlantParams
    rest_motor_rad: tuple[float, float, float]
    end_tick: int


def run_plotvars(run: IdentifyRun) -> np.ndarray:
    """The lab's PlotVar1..4 after every tick, shape ``(end_tick, 4)``. Raises :class:`RunFailed`."""
    from crslab.run.assemble import run_kept
    from crslab.run.board_run import RunError

    config = dataclasses.replace(run.config, plant=run.plant, rest_motor_rad=run.rest_motor_rad,
                                 log_signals=True)
    try:
        result = run_kept(config, run.end_tick)
    except RunError as exc:
        raise RunFailed(str(exc)) from None
    if not result.ok:
        raise RunFailed(result.message or str(result.status))
    log = result.log
    if log is None or len(log["plot"]) < run.end_tick:
        raise RunFailed(f"{config.build.source.name}: the run logged no Simulink PlotVars")
    return np.asarray(log["plot"][: run.end_tick], dtype=float)


class Runner:
    """Runs many :class:`IdentifyRun` s, ``jobs`` at a time (each in a process started from a clean,
    single-threaded forkserver, which then forks the lab's own worker), counting them for a
    progress display. Use as a context manager."""

    def __init__(self, jobs: int = 1, on_run: Callable[[], None] | None = None) -> None:
        self.jobs = max(1, jobs)
        self.on_run = on_run
        self.count = 0
        self._pool: ProcessPoolExecutor | None = None

    def __enter__(self) -> Runner:
        if self.jobs > 1:
            ctx = os_support.fork_server(["crslab.identify.runs", "crslab.run.board_run"])
            self._pool = ProcessPoolExecutor(self.jobs, mp_context=ctx)
        return self

    def __exit__(self, *exc: object) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)

    def run_all(self, runs: Sequence[IdentifyRun]) -> list[np.ndarray]:
        """The PlotVars of every run, in order. Raises :class:`RunFailed` for the first that failed."""
        if self._pool is None or len(runs) == 1:
            out = []
            for r in runs:
                out.append(run_plotvars(r))
                self._counted()
            return out
        futures = [self._pool.submit(run_plotvars, r) for r in runs]
        out = []
        for f in futures:
            out.append(f.result())
            self._counted()
        return out

    def _counted(self) -> None:
        self.count += 1
        if self.on_run is not None:
            self.on_run()


def lab_offsets(config: RunConfig) -> tuple[float, float, float]:
    """The motor angles the lab's encoders read at its resting pose: ``(0, offset_Enc2_rad,
    offset_Enc3_rad)`` as the lab file sets them (what the lab believes the resting pose is).
    Read from one tick of the lab, so whatever the file computes, it is the board's float value.
    Raises :class:`RunFailed` when that tick does not run."""
    from crslab.run.assemble import run_kept
    from crslab.run.board_run import RunError

    config = dataclasses.replace(config, log_signals=True, startup_ticks=10**9)
    try:
        result = run_kept(config, 1)
    except RunError as exc:
        raise RunFailed(str(exc)) from None
    log = result.log
    if log is None:
        raise RunFailed(result.message or str(result.status))
    enc = log["enc_rad"][0]
    rest = config.rest_motor_rad
    # encoders read offset + (true - rest); at tick 0 the arm is at rest
    return (0.0, float(enc[1]), float(enc[2])) if np.all(np.isfinite(enc)) else rest
