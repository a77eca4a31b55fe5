"""Issue 3: simulated throughput of ``crslab sim --fast`` on the default lab and tour against
MuJoCo's own fastest physics-only run of the same model (``mujoco.rollout``, zero controls, no
Python per step) for the same number of 1 ms steps (target ratio >= 0.8); and the time from
command start to the first lab() call with a cached build (target < 1 s)."""

from __future__ import annotations

import subprocess
import sys
import time

import mujoco
import numpy as np
from mujoco import rollout

from crslab.plant.model import load_model, motor_to_qpos
from crslab.plant.params import REST_MOTOR_RAD
from crslab.sim.api import make_config
from crslab.sim.session import Simulation
from crslab.sinks.sink import Sink

REPEATS = 5


def sim_rate(config, ticks: int) -> float:
    """Ticks per second of Simulation.run over ``ticks`` ticks (the worker already running)."""
    with Simulation(config) as sim:
        t = time.perf_counter()
        result = sim.run(ticks, Sink(), speed=None)
        dt = time.perf_counter() - t
    assert result.ok, result.message
    return ticks / dt


def rollout_rate(ticks: int) -> float:
    model = load_model()
    data = mujoco.MjData(model)
    data.qpos[:3] = motor_to_qpos(np.asarray(REST_MOTOR_RAD))
    mujoco.mj_forward(model, data)
    state = np.empty((1, mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_FULLPHYSICS)))
    mujoco.mj_getState(model, data, state[0], mujoco.mjtState.mjSTATE_FULLPHYSICS)
    control = np.zeros((1, ticks, model.nu))
    t = time.perf_counter()
    rollout.rollout(model, data, state, control)
    return ticks / (time.perf_counter() - t)


def first_lab_call_s() -> float:
    """Wall time of a whole `crslab sim` that makes one lab() call (upper bound on start-up)."""
    cmd = [sys.executable, "-m", "crslab", "sim", "--fast", "--no-startup-delay", "--duration", "0.001"]
    subprocess.run(cmd, check=True, capture_output=True)  # make sure the build is cached
    best = np.inf
    for _ in range(REPEATS):
        t = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        best = min(best, time.perf_counter() - t)
    return best


def run() -> list[str]:
    config = make_config()  # the default lab and the tour
    ticks = config.scenario.end_tick
    sims, rollouts = [], []
    for _ in range(REPEATS):  # interleaved, best of each: both see the same machine load
        sims.append(sim_rate(config, ticks))
        rollouts.append(rollout_rate(ticks))
    sim, physics = max(sims), max(rollouts)
    start = first_lab_call_s()
    return [
        f"crslab sim --fast (Lab 1, tour, {ticks} ticks): {sim:,.0f} ticks/s",
        f"mujoco.rollout physics only, same model and steps: {physics:,.0f} steps/s",
        f"ratio {sim / physics:.2f} (target >= 0.8)",
        f"command start to first lab() call (cached build): {start:.2f} s (target < 1 s)",
    ]
