"""Rerun scopes of a running lab: what Simulink, the scopes and Tera Term show, and the arm in 3D.

Everything is on the ``sim_time`` timeline (simulated time: tick k is k ms):

=========================  ===================================================================
entity                     holds
=========================  ===================================================================
``/scopes/simulink``       Simulink_PlotVar1..4 as Simulink receives them: every 5 ms, in steps
                           of 1e-4 (see :func:`crslab.scopes.signals.simulink_samples`)
``/scopes/motor_angle``    theta1motor..theta3motor, what lab() received (rad), every tick
``/scopes/torque/lab``     the lab's tau1..tau3 after lab() (command units), every tick
``/scopes/torque/applied`` what reached the motors (after the safety override, the clamp and the
                           motor board)
``/scopes/digital``        the safety flag, the GPIO34 / GPIO60 LED pin levels and whether the
                           motor board has cut the outputs, every tick
``/scopes/end_effector``   the end effector's x y z by the course's forward kinematics (m)
``/scopes/push``           a scenario's push at the end effector, world frame (N; 0 without one)
``/serial``                the serial lines (TextLog), at the tick that ended each line
``/arm/<body>``            each body's world pose (Transform3D), every 10 ms; its link shapes
                           from the MuJoCo model are static children (``/arm/<body>/shapes``)
=========================  ===================================================================

A blueprint puts the 3D view and the serial log on the left and one scope per group on the right.
Every chunk of ticks the simulation hands over is sent with a few ``send_columns`` calls. Rerun
(whose import starts threads) is imported after the worker process was forked: on the first
data, or in a background thread from :func:`preload` (as soon as the worker exists, so that its
half-second import overlaps the worker's start-up and the first ticks) or
:meth:`RerunSink.prepare`. ``crslab sim --rrd`` runs this sink in a writer process of its own
instead (:mod:`crslab.sinks.rerun_writer`).
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable
from pathlib import Path

import numpy as np

from crslab.scopes.arm3d import SHAPE_KINDS, quat_rotate
from crslab.scopes.rerun_stream import SIMULINK_ENTITY, SIMULINK_NAMES, open_recording
from crslab.scopes.signals import (
    DIGITAL,
    END_EFFECTOR,
    MOTOR,
    PUSH,
    SCALE,
    SIGNALS,
    SIMULINK,
    TORQUE,
    WORLD,
    WORLD_SIGNALS,
    Group,
    signal_values,
    simulink_samples,
)
from crslab.serial_lines import SerialLines
from crslab.sinks.sink import Sink
from crslab.world import World

TIMELINE = "sim_time"
FLUSH_TIMEOUT_S = 10.0
ARM_PERIOD_TICKS = 10
"""The 3D view's frame period: the arm's pose is logged every 10 ms (100 frames per second)."""

SCALAR_ENTITIES = {  # entity: (log column, series names)
    "/scopes/motor_angle": ("enc_rad", ["theta1motor", "theta2motor", "theta3motor"]),
    "/scopes/torque/lab": ("tau_lab", ["tau1", "tau2", "tau3"]),
    "/scopes/torque/applied": ("tau_applied", ["tau1 applied", "tau2 applied", "tau3 applied"]),
    "/scopes/end_effector": ("ee", ["x", "y", "z"]),
    "/scopes/push": ("push_force", ["Fx", "Fy", "Fz"]),
}
DIGITAL_ENTITY = "/scopes/digital"
DIGITAL_SIGNALS = [s for s in SIGNALS if s.group == DIGITAL]
"""The safety flag and the LED pin levels, as scopes.signals reads them from the log."""
DIGITAL_NAMES = [s.name for s in DIGITAL_SIGNALS]
WORLD_ENTITY = "/scopes/world"
WORLD_FORCE_SIGNALS = [s for s in WORLD_SIGNALS if s.group == WORLD]
"""The forces the arm presses on the world's fixtures (a world with fixtures only)."""
WORLD_FORCE_NAMES = [s.name for s in WORLD_FORCE_SIGNALS]
SCALE_ENTITY = "/scopes/scale"
SERIAL_ENTITY = "/serial"
ARM_ENTITY = "/arm"


def _time_column(ticks: np.ndarray) -> object:
    import rerun as rr

    return rr.TimeColumn(TIMELINE, duration=np.asarray(ticks, dtype=np.int64).astype("timedelta64[ms]"))


def blueprint(world: bool = False) -> object:
    """The layout: 3D view over the serial log on the left, the scopes stacked on the right (with
    the world's contact forces and the scale's grams under them in a world with fixtures)."""
    import rerun.blueprint as rrb

    def scope(origin: str, group: Group) -> object:
        return rrb.TimeSeriesView(origin=origin, name=f"{group.title} ({group.unit})")

    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(
                rrb.Spatial3DView(origin=ARM_ENTITY, name="arm"),
                rrb.TextLogView(origin=SERIAL_ENTITY, name="Tera Term"),
                row_shares=[3, 2],
            ),
            rrb.Vertical(
                scope(SIMULINK_ENTITY, SIMULINK),
                scope("/scopes/motor_angle", MOTOR),
                scope("/scopes/torque", TORQUE),
                scope(DIGITAL_ENTITY, DIGITAL),
                scope("/scopes/end_effector", END_EFFECTOR),
                scope("/scopes/push", PUSH),
                *([scope(WORLD_ENTITY, WORLD), scope(SCALE_ENTITY, SCALE)] if world else []),
            ),
            column_shares=[2, 3],
        ),
        rrb.TimePanel(state="collapsed"),
        collapse_panels=True,
    )


def _load_rerun_and_arm(loaded: list[object], world: object | None = None) -> None:
    try:
        import numpy.ma  # noqa: F401 - rerun imports it on the first blueprint: a tenth of a second
        import rerun  # noqa: F401 - the slow import, done here
        import rerun.blueprint  # noqa: F401

        from crslab.scopes.arm3d import ArmModel

        loaded.append(ArmModel(world))
    except Exception as exc:  # noqa: BLE001 - re-raised where the data arrives
        loaded.append(exc)


_preloads: list[tuple[threading.Thread, list[object]]] = []


def preload() -> None:
    """Import rerun and read the arm's model in a background thread now, for the next
    :class:`RerunSink` of this process to take. Call it after the worker was forked."""
    if not _preloads:
        loaded: list[object] = []
        thread = threading.Thread(target=_load_rerun_and_arm, args=(loaded,), name="crslab-rerun-import",
                                  daemon=True)
        thread.start()
        _preloads.append((thread, loaded))


def wait_preloaded() -> None:
    """Wait until what :func:`preload` started is done."""
    for thread, _ in _preloads:
        thread.join()


class RerunSink(Sink):
    """Send a run's scopes to a rerun viewer (``spawn=True``), an ``.rrd`` file, or both.

    ``on_status(line)`` receives the one-line notices (no display, viewer not started).
    """

    def __init__(self, *, rrd_path: Path | None = None, spawn: bool = False, name: str = "crslab",
                 on_status: Callable[[str], None] | None = None, world: World | None = None) -> None:
        if rrd_path is None and not spawn:
            raise ValueError("RerunSink needs an rrd_path, spawn=True or both")
        self.rrd_path = rrd_path
        self.spawn = spawn
        self.name = name
        self.world = world if world is not None and not world.is_free_air else None
        """The run's world, drawn with the arm (None: free air)."""
        self.on_status = on_status or (lambda line: print(line, file=sys.stderr))
        self.rec = None
        self.arm = None
        self.lines = SerialLines()
        self._pending: list[tuple[int, str]] = []
        self._closed = False
        self._loader: threading.Thread | None = None
        self._loaded: list[object] = []

    # -- start-up ----------------------------------------------------------------------------
    def prepare(self) -> None:
        """Import rerun and read the arm's model in the background (call after the fork), or take
        what :func:`preload` started."""
        if self._loader is None:
            if _preloads and self.world is None:
                self._loader, self._loaded = _preloads.pop()
                return
            self._loader = threading.Thread(target=_load_rerun_and_arm, args=(self._loaded, self.world),
                                            name="crslab-rerun-import", daemon=True)
            self._loader.start()

    def set_up(self) -> None:
        """Set the recording up now (rerun's import, the viewer or file, the blueprint, the arm's
        shapes) rather than on the first data."""
        self._ready()

    def _start(self) -> None:
        self.prepare()
        self._loader.join()
        loaded = self._loaded[0]
        if isinstance(loaded, Exception):
            raise loaded
        import rerun as rr

        self.rec, active = open_recording(rr, self.name, spawn=self.spawn, rrd_path=self.rrd_path,
                                          on_status=self.on_status, prefix="--rerun: ",
                                          blueprint=blueprint(self.world is not None))
        if not active:
            return
        self.arm = loaded
        self._log_static(rr)

    def _log_static(self, rr: object) -> None:
        rec = self.rec
        for entity, (_, names) in SCALAR_ENTITIES.items():
            rec.log(entity, rr.SeriesLines(names=names), static=True)
        rec.log(SIMULINK_ENTITY, rr.SeriesLines(names=SIMULINK_NAMES), static=True)
        rec.log(DIGITAL_ENTITY, rr.SeriesLines(names=DIGITAL_NAMES), static=True)
        if self.world is not None:
            rec.log(WORLD_ENTITY, rr.SeriesLines(names=WORLD_FORCE_NAMES), static=True)
            rec.log(SCALE_ENTITY, rr.SeriesLines(names=["scale_g"]), static=True)
        rec.log(ARM_ENTITY, rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
        for body in self.arm.bodies:
            for kind in SHAPE_KINDS:
                shapes = [s for s in body.shapes if s.kind == kind]
                if shapes:
                    rec.log(f"{ARM_ENTITY}/{body.name}/shapes/{kind}", _shapes(rr, kind, shapes), static=True)

    def _ready(self) -> bool:
        if self.rec is None and not self._closed:
            self._start()
        return self.arm is not None

    # -- data --------------------------------------------------------------------------------
    def on_serial(self, tick: int, data: bytes) -> None:
        self._pending.extend(self.lines.feed(tick, data))

    def _send_lines(self) -> None:
        import rerun as rr

        if self._pending and self._ready():
            ticks = np.array([t for t, _ in self._pending])
            self.rec.send_columns(SERIAL_ENTITY, indexes=[_time_column(ticks)],
                                  columns=rr.TextLog.columns(text=[line for _, line in self._pending],
                                                             level=["INFO"] * len(ticks)))
        self._pending = []

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        import rerun as rr

        tick = columns["tick"][:, 0]
        if not len(tick) or not self._ready():
            self._pending = []
            return
        rec = self.rec
        self._send_lines()
        every = [_time_column(tick)]
        for entity, (key, _) in SCALAR_ENTITIES.items():
            rec.send_columns(entity, indexes=every, columns=rr.Scalars.columns(scalars=columns[key]))
        digital = np.stack([signal_values(columns, s) for s in DIGITAL_SIGNALS], axis=1).astype(np.float64)
        rec.send_columns(DIGITAL_ENTITY, indexes=every, columns=rr.Scalars.columns(scalars=digital))
        if "egg_force" in columns:
            forces = np.stack([signal_values(columns, s) for s in WORLD_FORCE_SIGNALS], axis=1)
            rec.send_columns(WORLD_ENTITY, indexes=every, columns=rr.Scalars.columns(scalars=forces))
            grams = rr.Scalars.columns(scalars=columns["scale_g"])
            rec.send_columns(SCALE_ENTITY, indexes=every, columns=grams)
        sim_ticks, sim_values = simulink_samples(tick, columns["plot"])
        if len(sim_ticks):
            rec.send_columns(SIMULINK_ENTITY, indexes=[_time_column(sim_ticks)],
                             columns=rr.Scalars.columns(scalars=sim_values))
        frames = tick % ARM_PERIOD_TICKS == 0
        if frames.any():
            pos, quat = self.arm.poses(columns["qpos_dh_rad"][frames])
            at = [_time_column(tick[frames])]
            for b, body in enumerate(self.arm.moving):
                rec.send_columns(f"{ARM_ENTITY}/{body.name}", indexes=at,
                                 columns=rr.Transform3D.columns(translation=pos[:, b], quaternion=quat[:, b]))

    def close(self) -> None:
        if self._closed:
            return
        self._pending.extend(self.lines.finish())
        if self._pending:
            self._send_lines()
        self._closed = True
        if self.rec is not None:
            try:
                self.rec.flush(timeout_sec=FLUSH_TIMEOUT_S)
            except Exception as exc:  # noqa: BLE001 - a viewer that went away: one line, the file is kept
                why = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
                self.on_status(f"--rerun: the rerun viewer did not take the whole recording ({why})")
            self.rec.disconnect()


def _shapes(rr: object, kind: str, shapes: list) -> object:
    """One rerun archetype for all shapes of one kind on a body (MuJoCo sizes are half-sizes)."""
    pos = np.array([s.pos for s in shapes])
    quat = np.array([s.quat_xyzw for s in shapes])
    size = np.array([s.size for s in shapes])
    colors = (np.array([s.rgba for s in shapes]) * 255).round().astype(np.uint8)
    names = [s.name for s in shapes]
    if kind == "capsule":  # rerun's capsule runs from its origin along +z; MuJoCo's is centred
        axis = quat_rotate(np.roll(quat, 1, axis=1), np.array([0.0, 0.0, 1.0]))  # x y z w -> w x y z
        start = pos - axis * size[:, 1:2]
        return rr.Capsules3D(lengths=2 * size[:, 1], radii=size[:, 0], translations=start, quaternions=quat,
                             colors=colors, labels=names, show_labels=False, fill_mode="Solid")
    if kind == "cylinder":
        return rr.Cylinders3D(lengths=2 * size[:, 1], radii=size[:, 0], centers=pos, quaternions=quat,
                              colors=colors, labels=names, show_labels=False, fill_mode="Solid")
    if kind == "ellipsoid":
        return rr.Ellipsoids3D(half_sizes=size, centers=pos, quaternions=quat, colors=colors, labels=names,
                               show_labels=False, fill_mode="Solid")
    if kind == "sphere":
        return rr.Ellipsoids3D(half_sizes=np.repeat(size[:, :1], 3, axis=1), centers=pos, colors=colors,
                               labels=names, show_labels=False, fill_mode="Solid")
    return rr.Boxes3D(half_sizes=size, centers=pos, quaternions=quat, colors=colors, labels=names,
                      show_labels=False, fill_mode="Solid")

