"""What one run sends to the page, and what the page does to the run: a sink and a live control.

:class:`BrowserStream` is a :class:`~crslab.sinks.sink.Sink`: after every chunk of ticks it sends
one ``chunk`` message holding the serial bytes with the tick each left the board (what Tera Term
shows, at the time the board sends it), the arm's pose at 60 Hz of simulated time (DH and motor
angles, the safety flag, whether the motor board cut the outputs: the page poses its model of the
arm from the DH angles), and
the scope rows of every 5th tick (``Simulink_PlotVar1..4``, motor angles, commanded and applied
torques: :data:`SCOPE_SIGNALS`; one row each 5 ms, as the course's Simulink model samples them:
:data:`SCOPE_EVERY_TICKS`), packed as little-endian float32.

:class:`PageControl` is a :class:`~crslab.sim.running.PacedControl`: the server paces the run
(the worker runs a chunk, then the control waits until the wall clock reaches the chunk's end),
and while it waits it carries out what the page sent: stop, a new speed, the watched variables
(read and written between two ticks, as ``crslab sim``'s typed commands are), and the hand (a
spring from the grabbed point of a link to the mouse, passed to the worker as a force on that
link, as MuJoCo's viewer passes its mouse; let go and the force is gone).

>>> frame_ticks(np.arange(0, 40))
[0, 17, 34]
"""

from __future__ import annotations

import base64
import json
import time
from collections.abc import Callable

import numpy as np

from crslab.live.console import Command as VarCommand
from crslab.live.console import CommandError, VarConsole, format_value
from crslab.scenario.expect_events import ExpectOutcome
from crslab.sim.pacing import PAGE_CHUNKS, Pacer
from crslab.sim.running import RunningLab
from crslab.sinks.latest_pose import LatestPose
from crslab.sinks.sink import Ended, Sink

FRAME_HZ = 60
"""Poses of the arm per simulated second sent to the page (the 3D view)."""
INTERACTIVE_CHUNK_TICKS = 20
"""Ticks per chunk at real time (x speed) while the page acts, as ``crslab sim``'s: while the hand
holds the arm, and for :data:`INTERACTIVE_HOLD_TICKS` after any command, a command acts within 20
ms of simulated time. While it only watches, chunks are long (:data:`~crslab.sim.pacing.PAGE_CHUNKS`)."""
INTERACTIVE_HOLD_TICKS = 2000
SCOPE_EVERY_TICKS = 5
"""The page's scopes show the ticks divisible by this: one sample every 5 ms, as the course's
Simulink model (``simulink5ms_plotAndGains``) asks the board for its four ``Simulink_PlotVar`` every
5 ms; the board logs only those unless the run records its CSV or rrd (every tick)."""
SCOPE_SIGNALS = (
    "Simulink_PlotVar1",
    "Simulink_PlotVar2",
    "Simulink_PlotVar3",
    "Simulink_PlotVar4",
    "theta1motor",
    "theta2motor",
    "theta3motor",
    "tau1",
    "tau2",
    "tau3",
    "tau1_applied",
    "tau2_applied",
    "tau3_applied",
)
"""The scope columns of a chunk, in order (float32 each, one row per :data:`SCOPE_EVERY_TICKS`)."""
HAND_STIFFNESS_N_M = 400.0
"""The hand's spring from the grabbed point to the mouse (N/m)."""
HAND_DAMPING_N_S_M = 40.0
HAND_MAX_N = 300.0
"""The most the hand pulls with: enough to beat the hold controller (5 units on each motor) and
gravity, as the scenario's hand (120 N.m at each joint) does."""

Send = Callable[[bytes], None]


def frame_ticks(ticks: np.ndarray) -> list[int]:
    """The ticks among ``ticks`` that start a new 1/60 s frame of simulated time."""
    t = np.asarray(ticks, dtype=np.int64).reshape(-1)
    starts = (t * FRAME_HZ) // 1000 != ((t - 1) * FRAME_HZ) // 1000
    return t[starts].tolist()


def message(kind: str, **fields: object) -> bytes:
    """One message for the page, as JSON bytes.

    >>> message("event", tick=5000, text="hand to rest")
    b'{"type": "event", "tick": 5000, "text": "hand to rest"}'
    """
    return json.dumps({"type": kind, **fields}).encode()


class ArmPoses:
    """The arm's bodies' world poses from DH angles (the MuJoCo model's kinematics), and where a
    point fixed on a link is."""

    def __init__(self, world: object | None = None) -> None:
        from crslab.scopes.arm3d import ArmModel

        self.model = ArmModel(world)
        self.names = [b.name for b in self.model.moving]
        self.com_local = np.array([self.model.model.body_ipos[b.id] for b in self.model.moving])
        self.body_ids = [b.id for b in self.model.moving]
        self.nbody = int(self.model.model.nbody)

    def poses(self, qpos_dh_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(n, bodies, 3)`` positions (m) and ``(n, bodies, 4)`` quaternions ``x y z w``."""
        return self.model.poses(qpos_dh_rad)


def _rotate_xyzw(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    from crslab.scopes.arm3d import quat_rotate

    wxyz = np.concatenate([q[..., 3:], q[..., :3]], axis=-1).reshape(1, 4)
    return quat_rotate(wxyz, np.asarray(v, dtype=float).reshape(1, 3))[0]


class BrowserStream(Sink):
    """Sends each chunk of a run to the page through ``send`` (one message per chunk, once the run
    reached its end: :meth:`on_reached`; the last bytes of a run at its end: :meth:`on_end`)."""

    def __init__(self, send: Send, arm: ArmPoses, *, world: bool = False) -> None:
        self.send = send
        self.arm = arm
        self.world = world
        """The run's world has fixtures: each frame also carries the egg's force (N), the scale's
        grams and whether the egg broke."""
        self.serial: list[tuple[int, str]] = []
        self.blocks: list[dict[str, np.ndarray]] = []
        self.pose = LatestPose()
        """The arm's latest pose (its DH angles: the hand pulls from there)."""
        self.first_tick = 0
        self._frame = -1  # the 1/60 s frame of simulated time the last frame sent was in

    @property
    def last_qpos(self) -> np.ndarray | None:
        """The arm's latest DH angles (for the hand)."""
        return self.pose.qpos_dh_rad

    def on_motor_board(self, tick: int, joint: int, off: bool) -> None:
        self.send(message("motor_board", tick=tick, joint=joint, off=off))

    def on_expectation(self, outcome: ExpectOutcome) -> None:
        self.send(message("expectation", tick=outcome.tick, met=outcome.met, lines=outcome.lines(),
                          what=outcome.what))

    def on_serial(self, tick: int, data: bytes) -> None:
        self.serial.append((tick, data.decode("latin-1")))

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        self.blocks.append(columns)

    def on_reached(self, tick: int) -> None:
        self._send(tick)

    def on_end(self, result: Ended) -> None:
        self._send(result.end_tick)  # the bytes still on the serial line as the run ended

    def _send(self, tick: int) -> None:
        """The chunk up to ``tick`` (what came since the last), as one ``chunk`` message."""
        if not self.blocks and not self.serial:
            return
        fields: dict[str, object] = {"type": "chunk", "serial": self.serial}
        scope = b""
        log = _scope_rows(self.blocks) if self.blocks else None
        if log is not None:
            self.pose.on_log(log)
            fields.update(self._frames(log))
            scope = b', "scope": ' + self._scope(log)
        sent = round(time.monotonic(), 4)  # the machine's monotonic clock: where lag arises
        # the message as message("chunk", ...) writes it, its scope's base64 put in as it is (JSON
        # would copy and scan it for characters to escape, of which base64 has none)
        self.send(json.dumps(fields).encode()[:-1] + scope
                  + b', "first": %d, "tick": %d, "sent": %s}' % (self.first_tick, tick,
                                                                  json.dumps(sent).encode()))
        self.first_tick = tick
        self.serial, self.blocks = [], []

    def _frames(self, log: dict[str, np.ndarray]) -> dict[str, object]:
        """The rows that start a new 1/60 s frame of simulated time, and the chunk's last (a
        stopped run shows the latest pose)."""
        ticks = log["tick"][:, 0]
        frame = (ticks * FRAME_HZ) // 1000
        keep = np.empty(len(ticks), dtype=bool)
        keep[0] = frame[0] != self._frame
        keep[1:] = frame[1:] != frame[:-1]
        keep[-1] = True
        self._frame = int(frame[-1])
        frames = np.concatenate(
            [np.round(log["qpos_dh_rad"][keep], 5), np.round(log["enc_rad"][keep], 5)], axis=1
        )
        flags = np.concatenate([ticks[keep, None], log["safety"][keep], log["motor_board_off"][keep]], axis=1)
        if self.world and "egg_force" in log:
            world = np.concatenate([np.round(log["egg_force"][keep], 3), np.round(log["scale_g"][keep], 1),
                                    log["egg_broken"][keep]], axis=1).tolist()
            return {"frames": [[f[0], *a, f[1], f[2], *w] for f, a, w in zip(flags.tolist(), frames.tolist(),
                                                                            world)]}
        return {"frames": [[f[0], *a, f[1], f[2]] for f, a in zip(flags.tolist(), frames.tolist())]}

    @staticmethod
    def _scope(log: dict[str, np.ndarray]) -> bytes:
        """The chunk's ``scope`` field, as JSON: ``{"tick0": ..., "every": ..., "rows": ...,
        "data": "<base64>"}`` (row ``i`` is tick ``tick0 + i * every``)."""
        rows = np.concatenate([log["plot"], log["enc_rad"], log["tau_lab"], log["tau_applied"]], axis=1)
        data = base64.b64encode(rows.astype("<f4").tobytes())
        return b'{"tick0": %d, "every": %d, "rows": %d, "data": "%s"}' % (
            int(log["tick"][0, 0]), SCOPE_EVERY_TICKS, len(rows), data)


def _scope_rows(blocks: list[dict[str, np.ndarray]]) -> dict[str, np.ndarray] | None:
    """The page's rows of a chunk's scope log: one per tick divisible by :data:`SCOPE_EVERY_TICKS`
    (all of the log's rows when the board logged only those); None when there are none.

    >>> rows = _scope_rows([{"tick": np.arange(3, 14).reshape(-1, 1)}])
    >>> rows["tick"][:, 0].tolist(), _scope_rows([{"tick": np.arange(1, 5).reshape(-1, 1)}])
    ([5, 10], None)
    """
    log = blocks[0] if len(blocks) == 1 else {k: np.concatenate([b[k] for b in blocks]) for k in blocks[0]}
    ticks = log["tick"][:, 0]
    every = ticks % SCOPE_EVERY_TICKS == 0
    if not every.all():
        log = {k: v[every] for k, v in log.items()}
    return log if len(log["tick"]) else None


class Stopped(KeyboardInterrupt):
    """The page asked the run to stop (ends ``Simulation.run`` as its Ctrl-C does)."""


class PageControl:
    """The page's say in its run, a :class:`~crslab.sim.running.PacedControl`: the run's host hands
    it each command the page sends (:meth:`command`: stop, a new speed, the watched variables, the
    hand) as it arrives, while the lab is idle between two chunks; after every chunk it pushes the
    arm (:meth:`serve`). While the page acts (the hand holds the arm, or for
    :data:`INTERACTIVE_HOLD_TICKS` after any command) it asks for chunks of
    :data:`INTERACTIVE_CHUNK_TICKS` x speed; otherwise the run's pacer's (the page's chunks:
    :data:`~crslab.sim.pacing.PAGE_CHUNKS`)."""

    def __init__(self, send: Send, stream: BrowserStream, console: VarConsole, pacer: Pacer,
                 on_other: Callable[[dict], None]) -> None:
        self.send = send
        self.stream = stream
        self.console = console
        self.pacer = pacer
        """The run's pacer: a ``speed`` command changes its speed."""
        self.on_other = on_other
        self.hand: dict | None = None
        self._pushing = False
        self._anchor_prev: np.ndarray | None = None
        self._tick = 0
        self._acted_until = -1

    @property
    def speed(self) -> float | None:
        """The run's speed (x real time; None: as fast as possible)."""
        return self.pacer.speed

    def chunk_ticks(self, speed: float | None) -> int | None:
        """20 ms x ``speed`` while the page acts; None otherwise (the pacer's chunks), and as
        fast as possible (its chunks are short enough for Stop)."""
        if speed is None or (self.hand is None and self._tick >= self._acted_until):
            return None
        return max(1, round(INTERACTIVE_CHUNK_TICKS * speed))

    def serve(self, lab: RunningLab) -> None:
        """After a chunk, and after commands: push the arm while a hand holds it (once more, with
        no force, when it let go)."""
        self._tick = lab.tick
        self._push(lab)

    def command(self, lab: RunningLab, msg: dict) -> None:
        """Carry out one of the page's commands now (the lab is idle); raises :class:`Stopped`
        for ``stop``."""
        self._tick = lab.tick
        self._acted_until = lab.tick + INTERACTIVE_HOLD_TICKS
        kind = msg.get("type")
        if kind == "stop":
            raise Stopped
        if kind == "speed":
            self.pacer.set_speed(msg["speed"], lab.tick)
        elif kind == "vars":
            self.send(message("vars", **self.vars(lab, msg)))
        elif kind == "hand":
            self.hand = msg  # pushed from the next serve() on: the host serves it after commands
        elif kind == "release":
            self.hand = None
        else:
            self.on_other(msg)

    def vars(self, lab: RunningLab, msg: dict) -> dict:
        """A ``vars`` command's answer: ``ok``, the reply line, and for list/get the values."""
        cmd = VarCommand(msg["cmd"], msg.get("name"), msg.get("index"), msg.get("value"))
        try:
            reply = self.console.execute(lab, cmd)
        except CommandError as exc:
            return {"ok": False, "reply": str(exc), "cmd": cmd.verb}
        values = {}
        for var in self.console.watched.values():
            if var.length is None and (cmd.verb == "list" or var.name == cmd.name):
                value = lab.get(var.name)
                assert not isinstance(value, list)
                values[var.name] = format_value(var, value)
        return {"ok": True, "reply": reply, "cmd": cmd.verb, "values": values}

    def _push(self, lab: RunningLab) -> None:
        arm = self.stream.arm
        if self.hand is None or self.stream.last_qpos is None:
            if self._pushing:
                lab.push(np.zeros((arm.nbody, 6)))
                self._pushing = False
            self._anchor_prev = None
            return
        positions, quats = arm.poses(self.stream.last_qpos[None, :])  # only while a hand holds the arm
        pos, quat = positions[0], quats[0]
        i = arm.names.index(self.hand["body"])
        anchor = pos[i] + _rotate_xyzw(quat[i], self.hand["anchor"])
        com = pos[i] + _rotate_xyzw(quat[i], arm.com_local[i])
        velocity = np.zeros(3)
        dt = (self.chunk_ticks(self.speed) or PAGE_CHUNKS.fast_ticks) / 1000.0
        if self._anchor_prev is not None:
            velocity = (anchor - self._anchor_prev) / dt
        self._anchor_prev = anchor
        force = (
            HAND_STIFFNESS_N_M * (np.asarray(self.hand["target"]) - anchor) - HAND_DAMPING_N_S_M * velocity
        )
        size = float(np.linalg.norm(force))
        if size > HAND_MAX_N:
            force *= HAND_MAX_N / size
        forces = np.zeros((arm.nbody, 6))
        forces[arm.body_ids[i], :3] = force
        forces[arm.body_ids[i], 3:] = np.cross(anchor - com, force)
        lab.push(forces)
        self._pushing = True

