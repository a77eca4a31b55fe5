"""Apply a scenario event to the running worker, between ticks (in the worker process).

An event at tick k is applied before tick k runs, so tick k's encoder reading and lab() call
already see it. Faults act in the C framework (``crs_faults`` and ``estop_latched`` of
csrc/sim/sim.h); plant changes edit the MuJoCo model in place; writes go to the lab's globals.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from cffi import FFI

from crslab.scenario.events import (
    SIMULINK_INPUTS,
    WRIST_ESTOP_RAD,
    DeadMotor,
    EncoderGlitch,
    EncoderNoise,
    EndMass,
    Event,
    FrictionScale,
    HandMove,
    HandRelease,
    SetVariable,
    SimulinkInput,
    StuckEncoder,
    WristEstop,
)

if TYPE_CHECKING:
    from crslab.sim.worker import Worker

SIMULINK_INPUT_NAMES = tuple(f"SIMU_Var{i}_fromSIMU_16bit" for i in range(1, SIMULINK_INPUTS + 1))
"""The framework globals that hold what Simulink sent (csrc/sim/simulink_inputs.c)."""


@dataclass
class _ScenarioState:
    """What applying events needs to remember in one worker: the identified friction (so a
    scale is always relative to it) and the lab's Simulink inputs."""

    frictionloss: np.ndarray
    damping: np.ndarray
    tendon_frictionloss: np.ndarray
    tendon_damping: np.ndarray
    simulink_lib: object = None


def _state(worker: Worker) -> _ScenarioState:
    state = getattr(worker, "_scenario_state", None)
    if state is None:
        m = worker.model
        state = _ScenarioState(m.dof_frictionloss.copy(), m.dof_damping.copy(),
                               m.tendon_frictionloss.copy(), m.tendon_damping.copy())
        worker._scenario_state = state  # type: ignore[attr-defined]
    return state


def _simulink_lib(worker: Worker, state: _ScenarioState) -> object:
    if state.simulink_lib is None:
        ffi = FFI()
        ffi.cdef("\n".join(f"extern int {name};" for name in SIMULINK_INPUT_NAMES))
        state.simulink_lib = (ffi, ffi.dlopen(str(worker.config.build.shared_object)))
    return state.simulink_lib[1]  # type: ignore[index]


def apply_event(worker: Worker, event: Event) -> None:
    """Carry out ``event`` on the worker's plant, board or lab at the current tick."""
    sim = worker.sim
    faults = sim.faults
    if isinstance(event, HandMove):
        hand = sim.hand
        target = worker.rest_dh if event.target_dh_rad is None else event.target_dh_rad
        hand.active = 1
        hand.start_tick = sim.tick
        hand.duration_ticks = event.duration_ticks
        for j in range(3):
            hand.start_dh_rad[j] = float(worker.data.qpos[j])
            hand.target_dh_rad[j] = float(target[j])
    elif isinstance(event, HandRelease):
        sim.hand.active = 0
        for j in range(3):
            sim.hand.integral_rad_s[j] = 0.0
    elif isinstance(event, SetVariable):
        worker.set_var(event.name, event.index, event.value)
    elif isinstance(event, SimulinkInput):
        lib = _simulink_lib(worker, _state(worker))
        for number, value in event.values:
            setattr(lib, SIMULINK_INPUT_NAMES[number - 1], int(value))
    elif isinstance(event, EndMass):
        from crslab.plant.model import set_end_mass

        set_end_mass(worker.model, event.kg)
    elif isinstance(event, FrictionScale):
        state, m = _state(worker), worker.model
        m.dof_frictionloss[:] = state.frictionloss * event.scale
        m.dof_damping[:] = state.damping * event.scale
        m.tendon_frictionloss[:] = state.tendon_frictionloss * event.scale
        m.tendon_damping[:] = state.tendon_damping * event.scale
    elif isinstance(event, EncoderNoise):
        if event.rng_state:
            faults.rng_state = event.rng_state
        for j in event.joints:
            faults.noise_counts[j - 1] = float(event.counts[j - 1])
    elif isinstance(event, EncoderGlitch):
        if faults.glitch_tick != sim.tick:  # a new glitch; two at one tick add up
            faults.glitch_tick = sim.tick
            for j in range(3):
                faults.glitch_counts[j] = 0
        for j in range(3):
            faults.glitch_counts[j] += int(event.counts[j])
    elif isinstance(event, StuckEncoder):
        for j in event.joints:
            faults.stuck_encoder[j - 1] = int(event.stuck)
    elif isinstance(event, DeadMotor):
        for j in event.joints:
            faults.dead_motor[j - 1] = int(event.dead)
    elif isinstance(event, WristEstop):
        if abs(event.wrist_rad) > WRIST_ESTOP_RAD:
            sim.estop_latched = 1
    else:  # pragma: no cover - the loader only makes known kinds
        raise TypeError(f"no way to apply {event!r}")
