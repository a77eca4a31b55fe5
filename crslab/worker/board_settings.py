"""A run's settings and a scenario's events as the board takes them: one struct each
(``crs_board_settings``, ``crs_board_event`` of csrc/board/board_config.h), given to the board in one
call (``crs_board_configure``, ``crs_board_apply_event``). Python never writes the board's fields.

>>> from crslab.plant.plant_params import PlantParams
>>> plant = PlantParams.defaults()
>>> s = plant_settings(plant)
>>> s["stall_nm"] == list(plant.stall_nm), s["motor_gain_nm_per_unit"] == plant.motor_gain
(True, True)
>>> friction({"slide_pos_units": (1.0, 2.0, 3.0)}, 0.1)["slide_pos_units"]
[1.0, 2.0, 3.0]
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from crslab.framework_facts import MOTOR_BOARDS
from crslab.scenario.event import Event
from crslab.scenario.fault_events import EncoderGlitch, EncoderNoise, JointFault, WristEstop
from crslab.scenario.hand_events import HandMove, HandRelease
from crslab.scenario.lab_events import SimulinkInput
from crslab.scenario.push_events import Push

if TYPE_CHECKING:
    from crslab.plant.plant_params import PlantParams
    from crslab.worker.config import RunConfig


def friction(units: dict[str, tuple[float, ...]], transition_rad_s: float) -> dict[str, Any]:
    """The board's sliding friction (``crs_friction``) from :meth:`PlantParams.sliding_units`."""
    return {**{name: list(values) for name, values in units.items()}, "transition_rad_s": transition_rad_s}


def plant_settings(plant: PlantParams) -> dict[str, Any]:
    """What of the plant parameters the board takes: the drive (N.m, converted by the board into
    command units), the sliding friction, the encoder noise."""
    return {
        "motor_gain_nm_per_unit": plant.motor_gain, "stall_nm": list(plant.stall_nm),
        "backemf_nm_s_per_rad": list(plant.backemf_nm_s_per_rad), "drive_lag_s": plant.drive_lag_s,
        "friction": friction(plant.sliding_units(), plant.friction_transition_rad_s),
        "encoder_noise_counts": plant.encoder_noise_counts,
    }


def board_settings(config: RunConfig, *, trap_fp: bool = False, time_lab: bool = True) -> dict[str, Any]:
    """``crs_board_settings`` for the run ``config`` (its fields by name): the scope log every
    ``config.log_every_ticks`` ticks when the run logs its signals, else none."""
    return {
        "strict_nan": int(config.strict_nan), "motor_board": MOTOR_BOARDS[config.motor_board_model],
        "startup_ticks": config.startup_ticks, "budget_instructions": config.budget_instructions,
        "rest_motor_rad": [float(v) for v in config.rest_motor_rad],
        **plant_settings(config.plant),
        "hand_kp_nm_per_rad": config.hand.kp, "hand_ki_nm_per_rad_s": config.hand.ki,
        "hand_kd_nm_s_per_rad": config.hand.kd, "hand_max_nm": config.hand.max_nm,
        "break_when": int(config.build.break_when is not None), "trap_fp": int(trap_fp),
        "time_lab": int(time_lab), "log_every_ticks": config.log_every_ticks if config.log_signals else 0,
    }


def _joints(joints: tuple[int, ...]) -> int:
    return sum(1 << (j - 1) for j in joints)


def event_struct(c: Any, event: Event, rest_dh: Any) -> list[dict[str, Any]]:
    """The ``crs_board_event`` values that carry out ``event`` on the board (``c``: the board's
    constants; ``rest_dh``: where a hand move without a target goes); empty for an event the board
    does not carry out itself (a variable write, an expectation, a change of the model)."""
    match event:
        case HandMove():
            target = rest_dh if event.target_dh_rad is None else event.target_dh_rad
            return [{"kind": c.CRS_EVENT_HAND_MOVE, "duration_ticks": event.duration_ticks,
                     "values": [float(v) for v in target]}]
        case HandRelease():
            return [{"kind": c.CRS_EVENT_HAND_RELEASE}]
        case Push():
            return [{"kind": c.CRS_EVENT_PUSH, "on": int(not event.ends), "tick": event.tick,
                     "half_period_ticks": event.half_period_ticks,
                     "values": [float(v) for v in event.force_n]}]
        case EncoderNoise():
            return [{"kind": c.CRS_EVENT_ENCODER_NOISE, "joints": _joints(event.joints),
                     "rng_state": event.rng_state, "values": [float(v) for v in event.counts]}]
        case EncoderGlitch():
            return [{"kind": c.CRS_EVENT_ENCODER_GLITCH, "values": [float(v) for v in event.counts]}]
        case JointFault():
            kinds = {"stuck_encoder": c.CRS_EVENT_STUCK_ENCODER, "dead_motor": c.CRS_EVENT_DEAD_MOTOR}
            kind = kinds[event.fault]
            return [{"kind": kind, "joints": _joints(event.joints), "on": int(event.on)}]
        case WristEstop():
            return [{"kind": c.CRS_EVENT_WRIST_ESTOP}] if event.latches else []
        case SimulinkInput():
            return [{"kind": c.CRS_EVENT_SIMULINK_INPUT, "input": number, "value": int(value)}
                    for number, value in event.values]
    return []
