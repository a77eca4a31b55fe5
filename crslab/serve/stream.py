"""What the page does to its run in ``crslab serve``: a live control. (What the run sends to the
page is a sink's: :class:`crslab.sinks.page_stream.BrowserStream`.)

:class:`PageControl` is a :class:`~crslab.run.running.PacedControl`: the server paces the run
(the worker runs a chunk, then the control waits until the wall clock reaches the chunk's end),
and while it waits it carries out what the page sent: stop, a new speed, the watched variables
(read and written between two ticks, as ``crslab sim``'s typed commands are), and the hand (a
spring from the grabbed point of a link to the mouse, passed to the worker as a force on that
link, as MuJoCo's viewer passes its mouse; let go and the force is gone)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from crslab.framework_facts import TICKS_PER_S
from crslab.live.console import Command as VarCommand
from crslab.live.console import CommandError, VarConsole, format_value
from crslab.run.pacing import PAGE_CHUNKS, Pacer
from crslab.run.running import RunningLab
from crslab.sinks.page_stream import BrowserStream, Send, message

INTERACTIVE_CHUNK_TICKS = 20
"""Ticks per chunk at real time (x speed) while the page acts, as ``crslab sim``'s: while the hand
holds the arm, and for :data:`INTERACTIVE_HOLD_TICKS` after any command, a command acts within 20
ms of simulated time. While it only watches, chunks are long (:data:`~crslab.run.pacing.PAGE_CHUNKS`)."""
INTERACTIVE_HOLD_TICKS = 2000
HAND_STIFFNESS_N_M = 400.0
"""The hand's spring from the grabbed point to the mouse (N/m)."""
HAND_DAMPING_N_S_M = 40.0
HAND_MAX_N = 300.0
"""The most the hand pulls with: enough to beat the hold controller (5 units on each motor) and
gravity, as the scenario's hand (120 N.m at each joint) does."""


def _rotate_xyzw(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    from crslab.scopes.arm3d import quat_rotate

    wxyz = np.concatenate([q[..., 3:], q[..., :3]], axis=-1).reshape(1, 4)
    return quat_rotate(wxyz, np.asarray(v, dtype=float).reshape(1, 3))[0]


class Stopped(KeyboardInterrupt):
    """The page asked the run to stop (ends ``BoardRun.run`` as its Ctrl-C does)."""


class PageControl:
    """The page's say in its run, a :class:`~crslab.run.running.PacedControl`: the run's host hands
    it each command the page sends (:meth:`command`: stop, a new speed, the watched variables, the
    hand) as it arrives, while the lab is idle between two chunks; after every chunk it pushes the
    arm (:meth:`serve`). While the page acts (the hand holds the arm, or for
    :data:`INTERACTIVE_HOLD_TICKS` after any command) it asks for chunks of
    :data:`INTERACTIVE_CHUNK_TICKS` x speed; otherwise the run's pacer's (the page's chunks:
    :data:`~crslab.run.pacing.PAGE_CHUNKS`)."""

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
        dt = (self.chunk_ticks(self.speed) or PAGE_CHUNKS.fast_ticks) / TICKS_PER_S
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

