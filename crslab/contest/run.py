"""One contest run, as a TA runs one: the lab's own resting pose, nobody touching the arm, until the
arm comes to rest after its last motion (:mod:`crslab.contest.motion`), or ``--duration``.

- :func:`contest_config`: a run's configuration made a contest run (its world, its scenario, its
  resting pose, the world checked at that pose).
- :func:`run_contest`: the run, in chunks of :data:`CHUNK_TICKS`, ended as soon as the motion has
  (the same at any chunking: the log decides, and a chunk ends the run only after it).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from crslab.contest.motion import LONGEST_S, NO_MOTION_S, first_motion, still_since
from crslab.contest.offsets import Rest
from crslab.framework_facts import TICKS_PER_S
from crslab.run.assemble import NoLab, started
from crslab.run.board_run import DEFAULT_DEADLINE_S, NO_LIMITS, Limits
from crslab.run.diagnosis import Ending
from crslab.run.pacing import Chunks, Pacer
from crslab.run.status import RunResult, RunStatus
from crslab.scenario.event import seconds_to_tick
from crslab.sinks.memory import MemorySink
from crslab.sinks.sink import FanOut, Sink
from crslab.worker.config import RunConfig

CONTEST_WORLD = "contest"
CONTEST_SCENARIO = "hands_off"
"""Nobody touches the arm during a contest run."""
CHUNK_TICKS = TICKS_PER_S
"""How often (ticks) the run looks whether the motion has ended."""


def contest_config(config: RunConfig, rest: Rest) -> RunConfig:
    """``config`` (its world a contest world) logging the scope rows, with the arm resting at
    ``rest``. Raises ``WorldError`` (one line) when a fixture stands where the arm rests there."""
    from crslab.world import WorldError
    from crslab.world.layout_checks import check_layout

    world = config.world

    def fail(table: str, why: str) -> WorldError:
        return WorldError(f"the arm resting at {rest.motor_rad[1]:.4f} {rest.motor_rad[2]:.4f} rad "
                          f"({rest.said}): {world.source}: {table}: {why}")

    check_layout(world, rest.motor_rad, fail)
    return dataclasses.replace(config, rest_motor_rad=rest.motor_rad, log_signals=True)


class MotionWatch(Sink):
    """Watches the peg tip's path as the rows arrive: :attr:`ended` once the motion has ended
    (:mod:`crslab.contest.motion`), or the lab never moved the arm in :data:`NO_MOTION_S` after its
    first ``lab()`` call."""

    def __init__(self, startup_ticks: int) -> None:
        self.startup_ticks = startup_ticks
        self.ticks: list[np.ndarray] = []
        self.tips: list[np.ndarray] = []
        self.ended = False

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        self.ticks.append(np.asarray(columns["tick"]).reshape(-1))
        self.tips.append(np.asarray(columns["peg_tip"], dtype=np.float64).reshape(-1, 3))

    def on_reached(self, tick: int) -> None:
        if not self.ticks:
            return
        t = np.concatenate(self.ticks) / TICKS_PER_S
        tip = np.concatenate(self.tips)
        self.ticks, self.tips = [t * TICKS_PER_S], [tip]
        first = first_motion(t, tip)
        if first is None:
            self.ended = t[-1] >= self.startup_ticks / TICKS_PER_S + NO_MOTION_S
        else:
            self.ended = still_since(t, tip, first) is not None


def run_contest(config: RunConfig, *, duration_s: float | None = None,
                deadline_s: float | None = DEFAULT_DEADLINE_S, limits: Limits = NO_LIMITS,
                sinks: Sequence[Sink] = ()) -> RunResult:
    """Run ``config`` (a :func:`contest_config`) as fast as possible until the motion ends (or for
    ``duration_s`` simulated seconds, the start-up included), feeding ``sinks``; the result keeps
    every serial call and the scope log (up to the tick a crash or a hang stopped it). A lab
    without ``lab()`` ends ``no-lab`` before any tick; raises ``RunError`` when the worker cannot
    start."""
    end_tick = seconds_to_tick(duration_s if duration_s is not None else LONGEST_S)
    memory = MemorySink()
    watch = MotionWatch(config.startup_ticks) if duration_s is None else None
    try:
        with started(config, deadline_s=deadline_s, limits=limits) as sim:
            pacer = Pacer(None, sim.tick, chunks=Chunks(CHUNK_TICKS, CHUNK_TICKS))
            run = sim.start(end_tick, FanOut([memory, *([watch] if watch else []), *sinks]), pacer)
            ending = None
            while ending is None and not run.done:
                target, _ = run.next_chunk()
                ending = run.took(sim.run_chunk(target))
                if ending is None and watch is not None and watch.ended:
                    ending = Ending(RunStatus.OK, sim.tick)
            result = run.ended(ending or Ending(RunStatus.OK, sim.tick))
    except NoLab as exc:
        return RunResult(exc.status, 0, str(exc), lab_file=config.build.source)
    return dataclasses.replace(result, calls=memory.calls, sent=memory.sent, log=memory.log)
