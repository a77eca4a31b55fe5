"""What each kind of scenario event does to the running arm, board or lab (in the worker).

An event at tick k is applied before tick k runs, so tick k's encoder reading and lab() call
already see it. Faults act in the C framework (``crs_faults`` and ``estop_latched`` of
csrc/board/sim.h); plant changes edit the MuJoCo model in place; a push sets ``crs_push``, which
the C tick reads (csrc/plant/push.h); writes go to the lab's globals.
An expectation (``expect``) changes nothing: it notes what the worker sees, for the crslab
process to judge. Each event class of :data:`crslab.scenario.kinds.EVENT_CLASSES` has its effect here, found
from its class (:func:`effect_of` registers one).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any, Protocol, TypeVar

from crslab.plant.model import set_end_mass
from crslab.scenario.event import Event
from crslab.scenario.expect_events import Expect
from crslab.scenario.fault_events import EncoderGlitch, EncoderNoise, JointFault, WristEstop
from crslab.scenario.hand_events import HandMove, HandRelease
from crslab.scenario.lab_events import SetVariable, SimulinkInput
from crslab.scenario.plant_events import EndMass, FrictionScale
from crslab.scenario.push_events import Push

if TYPE_CHECKING:
    import mujoco
    import numpy as np

    from crslab.plant.plant_params import PlantParams
    from crslab.worker.config import SimConfig


class EffectTarget(Protocol):
    """What an effect may act on: the worker's board (``sim``, a ``crs_sim *``), its MuJoCo model
    and data, the run's configuration, and the worker's own ways to write the lab's variables,
    Simulink's inputs and the friction, or to note what an expectation sees
    (:class:`crslab.worker.board.Board` is one)."""

    sim: Any
    model: mujoco.MjModel
    data: mujoco.MjData
    config: SimConfig
    rest_dh: np.ndarray

    def set_var(self, name: str, index: int | None, value: float) -> None: ...

    def set_simulink_input(self, number: int, value: int) -> None: ...

    def set_friction(self, plant: PlantParams) -> None: ...

    def observe(self, var: tuple[str, int | None] | None) -> None: ...


E = TypeVar("E", bound=Event)
Effect = Callable[[EffectTarget, Any], None]
Apply = Callable[[EffectTarget, E], None]
EFFECTS: dict[type[Event], Effect] = {}
"""The effect of each event class."""


def effect_of(kind: type[E]) -> Callable[[Apply[E]], Apply[E]]:
    """Register the decorated function as what an event of class ``kind`` does."""

    def register(effect: Apply[E]) -> Apply[E]:
        EFFECTS[kind] = effect
        return effect

    return register


MODEL_EVENTS: tuple[type[Event], ...] = (EndMass, FrictionScale)
"""The kinds of events that edit the run's MuJoCo model in place (so its instance cannot share it)."""


def changes_model(events: Iterable[Event]) -> bool:
    """Whether any of ``events`` edits the MuJoCo model in place."""
    return any(isinstance(e, MODEL_EVENTS) for e in events)


def apply_event(worker: EffectTarget, event: Event) -> None:
    """Carry out ``event`` on the worker's plant, board or lab at the current tick."""
    effect = EFFECTS.get(type(event))
    if effect is None:  # pragma: no cover - every kind has one (tests/test_scenario_effects.py)
        raise TypeError(f"no effect is defined for scenario events of kind {event.kind!r}")
    effect(worker, event)


@effect_of(HandMove)
def _hand_move(worker: EffectTarget, e: HandMove) -> None:
    sim = worker.sim
    hand = sim.hand
    target = worker.rest_dh if e.target_dh_rad is None else e.target_dh_rad
    hand.active = 1
    hand.start_tick = sim.tick
    hand.duration_ticks = e.duration_ticks
    for j in range(3):
        hand.start_dh_rad[j] = float(worker.data.qpos[j])
        hand.target_dh_rad[j] = float(target[j])


@effect_of(HandRelease)
def _hand_release(worker: EffectTarget, e: HandRelease) -> None:
    hand = worker.sim.hand
    hand.active = 0
    for j in range(3):
        hand.integral_rad_s[j] = 0.0


@effect_of(SetVariable)
def _set_variable(worker: EffectTarget, e: SetVariable) -> None:
    worker.set_var(e.name, e.index, e.value)


@effect_of(SimulinkInput)
def _simulink_input(worker: EffectTarget, e: SimulinkInput) -> None:
    for number, value in e.values:
        worker.set_simulink_input(number, value)


@effect_of(EndMass)
def _end_mass(worker: EffectTarget, e: EndMass) -> None:
    set_end_mass(worker.model, e.kg)


@effect_of(FrictionScale)
def _friction_scale(worker: EffectTarget, e: FrictionScale) -> None:
    # relative to the run's own plant (its --plant file's friction), never cumulative
    base = worker.config.plant
    scaled = tuple(s * e.scale for s in base.friction_scale)
    worker.set_friction(dataclasses.replace(base, friction_scale=scaled))


@effect_of(Push)
def _push(worker: EffectTarget, e: Push) -> None:
    # the board works out each tick's force from the tick number (csrc/plant/push.c)
    push = worker.sim.push
    push.active = int(not e.ends)
    push.start_tick = e.tick
    push.half_period_ticks = e.half_period_ticks
    for k in range(3):
        push.force_n[k] = e.force_n[k]


@effect_of(EncoderNoise)
def _encoder_noise(worker: EffectTarget, e: EncoderNoise) -> None:
    faults = worker.sim.faults
    if e.rng_state:
        faults.rng_state = e.rng_state
    for j in e.joints:
        faults.noise_counts[j - 1] = float(e.counts[j - 1])


@effect_of(EncoderGlitch)
def _encoder_glitch(worker: EffectTarget, e: EncoderGlitch) -> None:
    sim = worker.sim
    faults = sim.faults
    if faults.glitch_tick != sim.tick:  # a new glitch; two at one tick add up
        faults.glitch_tick = sim.tick
        for j in range(3):
            faults.glitch_counts[j] = 0
    for j in range(3):
        faults.glitch_counts[j] += int(e.counts[j])


@effect_of(JointFault)
def _joint_fault(worker: EffectTarget, e: JointFault) -> None:
    flags = getattr(worker.sim.faults, e.fault)  # the crs_faults field named as the fault
    for j in e.joints:
        flags[j - 1] = int(e.on)


@effect_of(WristEstop)
def _wrist_estop(worker: EffectTarget, e: WristEstop) -> None:
    if e.latches:
        worker.sim.estop_latched = 1


@effect_of(Expect)
def _expect(worker: EffectTarget, e: Expect) -> None:
    var = e.variable
    worker.observe(None if var is None else (var.name, var.index))
