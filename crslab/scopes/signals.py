"""The signals a scope shows, named once: CSV columns, plot panels and rerun entities read them here.

A run's scope log (``RunConfig.log_signals``) has one row per tick (per ``log_every_ticks``: crslab
serve's page logs every 5th tick unless it records). Each :class:`Signal` is one
column of that table with its name, unit and the panel (:class:`Group`) it is drawn in.

>>> [g.title for g in GROUPS][2:5]
['Simulink_PlotVar1..4', 'safety flag, LEDs, motor board', 'arm pose (true DH angles)']
>>> csv_header()[:4]
['tick', 't [s]', 'theta1motor [rad]', 'theta2motor [rad]']
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from crslab.framework_facts import SIMULINK_PERIOD_MS, SIMULINK_SCALE
from crslab.world.world_facts import COLUMNS as WORLD_ROW

SIMULINK_PERIOD_TICKS = SIMULINK_PERIOD_MS
"""The board sends the four ``Simulink_PlotVar`` to Simulink every 5 ms (docs/framework.md section 8), as
``int32(SIMULINK_SCALE * value)``: Simulink sees them in steps of 1e-4 (framework_facts.h)."""


@dataclass(frozen=True)
class Group:
    """One scope panel: a title and the unit its signals share. A group that is not ``always``
    drawn is left out of a plot where every value is 0 (a run without a push)."""

    key: str
    title: str
    unit: str
    always: bool = True


@dataclass(frozen=True)
class Signal:
    """One scope trace: log column ``column``, element ``index`` (for LEDs: the bit), in ``group``."""

    name: str
    column: str
    index: int
    group: Group

    @property
    def unit(self) -> str:
        """The unit, from the signal's group."""
        return self.group.unit

    @property
    def csv_name(self) -> str:
        """The CSV header cell: name and unit, e.g. ``tau1 [command units]``."""
        return f"{self.name} [{self.unit}]"


MOTOR = Group("motor", "motor angles", "rad")
TORQUE = Group("torque", "torques", "command units")
SIMULINK = Group("simulink", "Simulink_PlotVar1..4", "lab units")
DIGITAL = Group("digital", "safety flag, LEDs, motor board", "0/1")
POSE = Group("pose", "arm pose (true DH angles)", "rad")
END_EFFECTOR = Group("ee", "end effector (course FK)", "m")
PUSH = Group("push", "push at the end effector (world frame)", "N", always=False)
GROUPS: tuple[Group, ...] = (MOTOR, TORQUE, SIMULINK, DIGITAL, POSE, END_EFFECTOR, PUSH)

SIGNALS: tuple[Signal, ...] = (
    *(Signal(f"theta{j + 1}motor", "enc_rad", j, MOTOR) for j in range(3)),
    *(Signal(f"tau{j + 1}", "tau_lab", j, TORQUE) for j in range(3)),
    *(Signal(f"tau{j + 1}_applied", "tau_applied", j, TORQUE) for j in range(3)),
    *(Signal(f"Simulink_PlotVar{k + 1}", "plot", k, SIMULINK) for k in range(4)),
    Signal("safety", "safety", 0, DIGITAL),
    Signal("GPIO34", "leds", 0, DIGITAL),   # LED on the control card: pin level
    Signal("GPIO60", "leds", 1, DIGITAL),   # LED on the e-stop box (active low): pin level
    Signal("motor_board_off", "motor_board_off", 0, DIGITAL),  # 1: the motor board cut every output
    *(Signal(f"th{j + 1}_dh", "qpos_dh_rad", j, POSE) for j in range(3)),
    # the true end effector: the course's forward kinematics of the plant's angles, in metres
    *(Signal(f"ee_{axis}", "ee", k, END_EFFECTOR) for k, axis in enumerate("xyz")),
    # a scenario's push (crslab/scenario/push_events.py): this tick's force, 0 without one
    *(Signal(f"push_f{axis}", "push_force", k, PUSH) for k, axis in enumerate("xyz")),
)
"""Every signal, in CSV column order (after ``tick`` and ``t [s]``)."""

WORLD = Group("world", "world contacts", "N")
PEG_TIP = Group("peg_tip", "peg tip, its depth in the hole and its place in the groove", "m")
SCALE = Group("scale", "the egg's scale", "g")
EGG = Group("egg", "the egg", "0/1")
_WORLD_UNIT_GROUPS = {g.unit: g for g in (
    WORLD, PEG_TIP, SCALE, EGG,
    Group("egg_touch", "how fast the peg came down onto the egg", "m/s", always=False),
    Group("egg_break", "what broke the egg (1 the press, 2 a side hit, 3 a fall)", "code", always=False),
    Group("groove_segment", "the groove's segment nearest the peg", "index", always=False))}
WORLD_GROUPS: tuple[Group, ...] = tuple(_WORLD_UNIT_GROUPS.values())
WORLD_SIGNALS: tuple[Signal, ...] = tuple(
    Signal(c.name if c.width == 1 else f"{c.name}_{'xyz'[j]}", c.name, j, _WORLD_UNIT_GROUPS[c.unit])
    for c in WORLD_ROW for j in range(c.width))
"""What a world with fixtures adds to the scope log (docs/worlds.md): the world row's columns, as C
names them (:data:`crslab.world.world_facts.COLUMNS`): the peg's tip and depth, the force the
arm presses on each fixture, the scale's grams, the egg's break, the peg's place in the groove. A
free-air run (world ``none``) has none of these columns."""


def signals_of(log: dict[str, np.ndarray] | None) -> tuple[Signal, ...]:
    """The signals a scope log holds: :data:`SIGNALS`, and :data:`WORLD_SIGNALS` when it has the
    world's columns.

    >>> len(signals_of({})), len(signals_of({"egg_force": np.zeros((0, 1))})) - len(SIGNALS)
    (26, 23)
    """
    return SIGNALS + WORLD_SIGNALS if log is not None and "egg_force" in log else SIGNALS


C_FLOAT_COLUMNS = frozenset({"enc_rad", "tau_lab", "plot"})
"""Log columns that are C ``float`` variables in the lab (logged widened to double)."""


def csv_header(signals: tuple[Signal, ...] = SIGNALS) -> list[str]:
    """The CSV header: ``tick``, ``t [s]``, then every signal with its unit (``signals``: those of a
    free-air run, or :data:`SIGNALS` + :data:`WORLD_SIGNALS`)."""
    return ["tick", "t [s]", *(s.csv_name for s in signals)]


def signal_values(log: dict[str, np.ndarray], signal: Signal) -> np.ndarray:
    """One signal's values, one per logged row (LEDs as 0/1 pin levels; the lab's C floats as
    float32, so they print as the lab's values do).

    >>> log = {"leds": np.array([[0], [1], [2], [3]], np.uint32)}
    >>> signal_values(log, SIGNALS[15]).tolist()      # GPIO60, bit 1
    [0, 0, 1, 1]
    """
    col = log[signal.column]
    if signal.column == "leds":
        return ((col[:, 0] >> signal.index) & 1).astype(np.int32)
    if signal.column in C_FLOAT_COLUMNS:
        return col[:, signal.index].astype(np.float32)
    return col[:, signal.index]


def simulink_samples(tick: np.ndarray, plot: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """What Simulink receives: the rows at every 5th tick, each value sent as int32(10000 * value).

    The board computes ``10000 * value`` in single precision and stores it in a 32-bit integer,
    which truncates toward zero; Simulink divides by 10000 again.

    >>> t, v = simulink_samples(np.arange(11), np.tile([2 / 3, -2 / 3, 4e-5, 1.5], (11, 1)))
    >>> t.tolist()
    [0, 5, 10]
    >>> v[0].tolist()          # truncated, not rounded: 6666.67 is sent as 6666
    [0.6666, -0.6666, 0.0, 1.5]
    """
    tick = np.asarray(tick).reshape(-1)
    keep = tick % SIMULINK_PERIOD_TICKS == 0
    scaled = np.asarray(plot)[keep].astype(np.float32) * np.float32(SIMULINK_SCALE)
    sent = np.trunc(scaled).astype(np.int32)
    return tick[keep], sent.astype(np.float64) / SIMULINK_SCALE
