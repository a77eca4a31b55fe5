"""What one run sends to the page in ``crslab serve``: :class:`BrowserStream`, a
:class:`~crslab.sinks.sink.Sink` that after every chunk of ticks sends one ``chunk`` message holding
the serial bytes with the tick each left the board (what Tera Term shows, at the time the board
sends it), the arm's pose at 60 Hz of simulated time (DH and motor angles, the safety flag,
whether the motor board cut the outputs: the page poses its model of the arm from the DH angles;
packed as little-endian float64 rows, :func:`packed_rows`), and the scope rows of every 5th tick
(``Simulink_PlotVar1..4``, motor angles, commanded and applied torques: :data:`SCOPE_SIGNALS`;
one row each 5 ms, as the course's Simulink model samples them: :data:`SCOPE_EVERY_TICKS`), packed
as little-endian float32. What the page does to the run is
crslab/serve/stream.py's (:class:`~crslab.serve.stream.PageControl`).

>>> frame_ticks(np.arange(0, 40))
[0, 17, 34]
"""

from __future__ import annotations

import base64
import json
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from crslab.scenario.expect_events import ExpectOutcome
from crslab.sinks.latest_pose import LatestPose
from crslab.sinks.sink import Ended, Sink

if TYPE_CHECKING:
    from crslab._bindings import PageRows


class LoggedBlock(Protocol):
    """What :meth:`BrowserStream.rows_from` reads: a run's shared block (crslab/run/shared_block.py's
    ``SharedBlock``), whose ``view.log`` is the board's scope log of the chunk."""

    @property
    def view(self) -> Any: ...


FRAME_HZ = 60
"""Poses of the arm per simulated second sent to the page (the 3D view)."""
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
WORLD_SCOPE_SIGNALS = ("scale_g",)
"""In a world with fixtures, the columns after :data:`SCOPE_SIGNALS`: the egg's force as its scale
shows it (g), the contest's band drawn over it on the page."""

Send = Callable[[bytes], None]
"""Where a page's messages go."""


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
        self._block: LoggedBlock | None = None
        self._rows: PageRows | None = None

    def rows_from(self, block: LoggedBlock) -> None:
        """Take each message's scope rows straight from the run's shared block, packed there in C
        (:class:`~crslab._bindings.PageRows`: the same bytes), not from :meth:`on_log`: a run host's
        page runs, whose other sinks take no rows (the run leaves them in the block:
        ``ChunkedRun.rows_in_block``)."""
        from crslab._bindings import PageRows
        from crslab.world.world_facts import WORLD_COLUMNS

        starts, at = {}, 0
        for name, width in WORLD_COLUMNS.items():
            starts[name] = at
            at += width
        world = (starts["egg_force"], starts["scale_g"], starts["egg_broken"]) if self.world else None
        self._block, self._rows = block, PageRows(SCOPE_EVERY_TICKS, world)
        self.pose = _PackedPose(self._rows, self.pose)

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
        self._send(tick, logged=self._block is not None)

    def on_end(self, result: Ended) -> None:
        # the bytes still on the serial line as the run ended, and the rows the block still holds
        self._send(result.end_tick, logged=self._block is not None and self._block.view.log.count > 0)

    def _send(self, tick: int, logged: bool = False) -> None:
        """The chunk up to ``tick`` (what came since the last), as one ``chunk`` message; ``logged``:
        the block holds the chunk's rows (:meth:`rows_from`), and a message goes whatever they are."""
        if self._rows is not None and self._block is not None:
            self._send_packed(tick, logged)
            return
        if not self.blocks and not self.serial:
            return
        # the message as message("chunk", ...) writes it, its packed fields put in as they are (JSON
        # would copy and scan their base64 for characters to escape, of which base64 has none)
        parts = [b'{"type": "chunk", "serial": ', json.dumps(self.serial).encode() if self.serial else b"[]"]
        log = _scope_rows(self.blocks) if self.blocks else None
        if log is not None:
            self.pose.on_log(log)
            parts += [b', "frames": ', self._frames(log), b', "scope": ',
                      self._scope(log, self.world and "scale_g" in log)]
        sent = round(time.monotonic(), 4)  # the machine's monotonic clock: where lag arises
        # (a finite float's JSON is its repr: json.dumps writes float.__repr__)
        parts.append(b', "first": %d, "tick": %d, "sent": %s}' % (self.first_tick, tick, repr(sent).encode()))
        self.send(b"".join(parts))
        self.first_tick = tick
        self.serial, self.blocks = [], []

    def _send_packed(self, tick: int, logged: bool) -> None:
        """:meth:`_send` for rows taken from the block (:meth:`rows_from`): the same message."""
        assert self._rows is not None and self._block is not None
        if not logged and not self.serial:
            return
        packed = self._rows.take(self._block.view) if logged else b""
        if packed:
            self.pose.taken()
        sent = round(time.monotonic(), 4)
        self.send(b'{"type": "chunk", "serial": %s%s, "first": %d, "tick": %d, "sent": %s}' % (
            serial_json(self.serial), packed, self.first_tick, tick, repr(sent).encode()))
        self.first_tick = tick
        self.serial = []

    def _frames(self, log: dict[str, np.ndarray]) -> bytes:
        """The chunk's ``frames`` field, as JSON: the rows that start a new 1/60 s frame of
        simulated time, and the chunk's last (a stopped run shows the latest pose), packed
        (:func:`packed_rows`): ``tick, th1..3 (DH rad), theta1..3motor (rad), safety, motor
        board off`` and in a world with fixtures ``egg force (N), scale (g), egg broken``."""
        ticks = log["tick"][:, 0]
        frame = (ticks * FRAME_HZ) // 1000
        keep = np.empty(len(ticks), dtype=bool)
        keep[0] = frame[0] != self._frame
        keep[1:] = frame[1:] != frame[:-1]
        keep[-1] = True
        self._frame = int(frame[-1])
        columns = [log["tick"], log["qpos_dh_rad"], log["enc_rad"], log["safety"], log["motor_board_off"]]
        if self.world and "egg_force" in log:
            columns += [log["egg_force"], log["scale_g"], log["egg_broken"]]
        return packed_rows(np.concatenate(columns, axis=1, dtype="<f8")[keep])

    @staticmethod
    def _scope(log: dict[str, np.ndarray], world: bool = False) -> bytes:
        """The chunk's ``scope`` field, as JSON: ``{"tick0": ..., "every": ..., "rows": ...,
        "columns": ..., "data": "<base64>"}`` (row ``i`` is tick ``tick0 + i * every``; its columns
        :data:`SCOPE_SIGNALS`, and in a ``world`` with fixtures :data:`WORLD_SCOPE_SIGNALS`)."""
        parts = [log["plot"], log["enc_rad"], log["tau_lab"], log["tau_applied"]]
        if world:
            parts += [np.asarray(log[n]).reshape(len(log["tick"]), -1)[:, :1] for n in WORLD_SCOPE_SIGNALS]
        rows = np.concatenate(parts, axis=1)
        data = base64.b64encode(rows.astype("<f4").tobytes())
        return b'{"tick0": %d, "every": %d, "rows": %d, "columns": %d, "data": "%s"}' % (
            int(log["tick"][0, 0]), SCOPE_EVERY_TICKS, len(rows), rows.shape[1], data)


class _PackedPose(LatestPose):
    """The arm's latest pose for a stream whose rows are packed in C (:meth:`BrowserStream.rows_from`):
    the last packed row's, read off its :class:`~crslab._bindings.PageRows` when asked (only a page
    whose hand holds the arm asks), not after every chunk."""

    def __init__(self, rows: PageRows, was: LatestPose) -> None:
        self._rows = rows
        self._stale = False
        super().__init__()
        self.qpos_dh_rad, self.egg_broken = was.qpos_dh_rad, was.egg_broken

    def taken(self) -> None:
        """The rows of a chunk were packed: the pose is its last row's."""
        self._stale = True
        self.egg_broken = self.egg_broken or self._rows.egg_broken

    @property  # type: ignore[override]
    def qpos_dh_rad(self) -> np.ndarray | None:
        if self._stale:
            self._qpos, self._stale = self._rows.qpos_dh_rad, False
        return self._qpos

    @qpos_dh_rad.setter
    def qpos_dh_rad(self, value: np.ndarray | None) -> None:
        self._qpos, self._stale = value, False


def serial_json(serial: list[tuple[int, str]]) -> bytes:
    """A chunk's ``serial`` field: ``json.dumps(serial)``'s bytes, each text escaped by the
    function ``json.dumps`` escapes it with, without making a JSON encoder for every chunk.

    >>> serial = [(4100, "0.00 -24.06\\n\\r"), (4101, '"\\x7f\\xe9')]
    >>> serial_json(serial) == json.dumps(serial).encode(), serial_json([])
    (True, b'[]')
    """
    return b"[%s]" % b", ".join(b"[%d, %s]" % (tick, _escaped(text).encode()) for tick, text in serial)


_escaped = json.encoder.encode_basestring_ascii  # what json.dumps escapes a text with (ensure_ascii)


def packed_rows(rows: np.ndarray) -> bytes:
    """Rows of numbers as a JSON object: ``{"columns": ..., "rows": ..., "data": "<base64>"}``, the
    data little-endian float64, row after row (the page decodes them as they come: app.js).

    >>> packed_rows(np.array([[17.0, -0.5], [34.0, 1.25]]))
    b'{"columns": 2, "rows": 2, "data": "AAAAAAAAMUAAAAAAAADgvwAAAAAAAEFAAAAAAAAA9D8="}'
    >>> unpacked_rows({"columns": 2, "rows": 2, "data": "AAAAAAAAMUAAAAAAAADgvwAAAAAAAEFAAAAAAAAA9D8="})
    [[17.0, -0.5], [34.0, 1.25]]
    """
    data = base64.b64encode(np.ascontiguousarray(rows, dtype="<f8").tobytes())
    return b'{"columns": %d, "rows": %d, "data": "%s"}' % (rows.shape[1], rows.shape[0], data)


def unpacked_rows(field: dict) -> list[list[float]]:
    """The rows :func:`packed_rows` packed (what the page's script does with a chunk's frames)."""
    rows = np.frombuffer(base64.b64decode(field["data"]), "<f8").reshape(field["rows"], field["columns"])
    return rows.tolist()


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
