"""What each kind of scenario event does to the running arm, board or lab (in the worker).

An event at tick k is applied before tick k runs, so tick k's encoder reading and lab() call
already see it. What acts on the board (the hand, a push, faults, the e-stop, Simulink's inputs, the
sliding friction) is one ``crs_board_event`` the board applies itself
(:func:`crslab.worker.board_settings.event_struct`, csrc/board/board_config.c); plant changes edit
the MuJoCo model in place; writes go to the lab's globals.
An expectation (``expect``) changes nothing: it notes what the worker sees, for the crslab
process to judge. Each event class of :data:`crslab.scenario.kinds.EVENT_CLASSES` has its effect here, found
from its class (:func:`effect_of` registers one).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any, Protocol, TypeVar

from crslab._bindings import constants
from crslab.plant.model import set_end_mass
from crslab.scenario.event import Event
from crslab.scenario.expect_events import Expect
from crslab.scenario.fault_events import EncoderGlitch, EncoderNoise, JointFault, WristEstop
from crslab.scenario.hand_events import HandMove, HandRelease
from crslab.scenario.lab_events import SetVariable, SimulinkInput
from crslab.scenario.plant_events import EndMass, FrictionScale
from crslab.scenario.push_events import Push
from crslab.worker.board_settings import event_struct

if TYPE_CHECKING:
    import mujoco
    import numpy as np

    from crslab.plant.plant_params import PlantParams
    from crslab.worker.config import RunConfig


class EffectTarget(Protocol):
    """What an effect may act on: the board (one ``crs_board_event`` at a time), its MuJoCo model
    and data, the run's configuration, and the worker's own ways to write the lab's variables and
    the friction, or to note what an expectation sees (:class:`crslab.worker.board.Board` is one)."""

    model: mujoco.MjModel
    data: mujoco.MjData
    config: RunConfig
    rest_dh: np.ndarray

    def board_event(self, fields: dict[str, Any]) -> None: ...

    def set_var(self, name: str, index: int | None, value: float) -> None: ...

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


def _on_board(worker: EffectTarget, e: Event) -> None:
    # the board carries these out itself (crs_board_apply_event, csrc/board/board_config.c)
    for fields in event_struct(constants, e, worker.rest_dh):
        worker.board_event(fields)


BOARD_EVENTS = (HandMove, HandRelease, Push, EncoderNoise, EncoderGlitch, JointFault, WristEstop,
                SimulinkInput)
"""The kinds of events the board carries out itself."""
for _kind in BOARD_EVENTS:
    effect_of(_kind)(_on_board)


@effect_of(SetVariable)
def _set_variable(worker: EffectTarget, e: SetVariable) -> None:
    worker.set_var(e.name, e.index, e.value)


@effect_of(EndMass)
def _end_mass(worker: EffectTarget, e: EndMass) -> None:
    set_end_mass(worker.model, e.kg)


@effect_of(FrictionScale)
def _friction_scale(worker: EffectTarget, e: FrictionScale) -> None:
    # relative to the run's own plant (its --plant file's friction), never cumulative
    base = worker.config.plant
    scaled = tuple(s * e.scale for s in base.friction_scale)
    worker.set_friction(dataclasses.replace(base, friction_scale=scaled))


@effect_of(Expect)
def _expect(worker: EffectTarget, e: Expect) -> None:
    var = e.variable
    worker.observe(None if var is None else (var.name, var.index))
