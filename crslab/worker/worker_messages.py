"""The messages between the crslab process and its worker (crslab/worker/main.py), typed, and the
one place the worker's replies are checked.

A worker holds board instances (:class:`crslab.worker.board.Board`), each named by a whole number
the crslab process chose; every request about one carries its ``instance``. The crslab process asks
(:data:`Request`): :class:`Open` an instance (a WebAssembly worker only: its shared block follows
the message as a passed descriptor), :class:`Run` it to a tick, :class:`RunMany` instances each to
its tick in one request, :class:`Get` or :class:`Set` a watched variable, :class:`Push` the arm,
:class:`Break` into the debugger, :class:`Stop` an instance (its last counters, and it is gone),
:class:`End` the worker. The worker answers (:data:`Reply`): for an instance opened, :class:`Ready`
(or :class:`Failed`, :class:`Trapped`: it is not open), then :class:`Ran` for a run (one per
instance of a :class:`RunMany`, in its order), :class:`Value` or :class:`Error` for the others,
:class:`Stopped` last. Serial bytes and scope rows never travel here: each instance's board writes
them into its own shared block (:mod:`crslab.run.shared_block`), where they outlive the worker.

On the pipe every message is a tuple of plain data, its kind first (:meth:`Message.wire`): the
crslab process never unpickles a class the worker names. A native lab shares the worker's process
and may write anything into the pipe, so a reply is unpickled with only plain data and numeric
arrays allowed (:mod:`crslab.worker.worker_reply`), then :func:`read_reply` checks it is the reply
due, field by field; anything else is :class:`~crslab.worker.worker_reply.UnreadableReply`.

>>> Run(0, 5000).wire()
('run', 0, 5000)
>>> read_reply(("value", 1.5), Value, Error)
Value(value=1.5)
>>> read_reply(("ran", 0, 0, "5000", {}, [], [], None), Ran)
Traceback (most recent call last):
...
crslab.worker.worker_reply.UnreadableReply: its ran reply holds tick = '5000', not a whole number
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, NamedTuple, dataclass_transform

from crslab.scenario.expect_events import Observation
from crslab.worker.run_stats import BOARD_COUNTERS, RunStats
from crslab.worker.worker_reply import UnreadableReply

if TYPE_CHECKING:
    from crslab.worker.config import RunConfig


@dataclass_transform(frozen_default=True)
class Message:
    """A message on the pipe: its :attr:`KIND` (the class's name in lower case) and its fields.
    Every subclass is a frozen dataclass."""

    KIND: ClassVar[str] = ""
    NAMES: ClassVar[tuple[str, ...]] = ()
    """Its fields' names, in order."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        cls.KIND = cls.__name__.lower()
        dataclass(frozen=True)(cls)
        cls.NAMES = tuple(f.name for f in dataclasses.fields(cls))  # type: ignore[arg-type]

    def wire(self) -> tuple:
        """The message as it travels: ``(KIND, field, ...)``, plain data only."""
        return (self.KIND, *[plain(getattr(self, name)) for name in self.NAMES])


_AS_IS = (int, float, str, bool, type(None), dict)
"""What travels as it is (a table is the counters': plain already)."""


def plain(value: object) -> object:
    """``value`` with the typed parts of a reply (observations, motor-board events) as plain data:
    what :func:`read_reply` reads back."""
    if type(value) in _AS_IS:
        return value
    if isinstance(value, Observation):
        return {**dataclasses.asdict(value), "motor_board_off": int(value.motor_board_off)}
    if isinstance(value, MotorBoardEvent):
        return (value.tick, value.joint, int(value.off))
    if isinstance(value, RunStats):
        return value.wire()
    if isinstance(value, tuple | list):
        return [plain(v) for v in value]
    return value


# -- the crslab process asks --------------------------------------------------------------------
class Open(Message):
    """Add instance ``instance`` running ``config``: a call of its firmware running longer than
    ``deadline_s`` is interrupted (None: never). Its shared block follows on the pipe as a
    descriptor (:func:`multiprocessing.reduction.send_handle`)."""

    instance: int
    config: RunConfig
    deadline_s: float | None


class Run(Message):
    """Run instance ``instance`` up to ``until_tick`` (scenario events applied on their ticks)."""

    instance: int
    until_tick: int


class RunMany(Message):
    """Run each instance of ``targets`` (``(instance, until_tick)`` pairs) to its tick, one after
    the other: one :class:`Ran` reply each, in this order."""

    targets: list


class Get(Message):
    """A watched variable's value."""

    instance: int
    name: str


class Set(Message):
    """Write a watched variable (``index``: one element of a watched array)."""

    instance: int
    name: str
    index: int | None
    value: float


class Push(Message):
    """A force and torque on each body (MuJoCo ``xfrc_applied``, rows of six) until the next push."""

    instance: int
    body_forces: list


class Break(Message):
    """Call ``crs_debug_break`` (a debugged run: the debugger arms its breakpoint on ``lab()``)."""

    instance: int


class Stop(Message):
    """Send the instance's last counters and remove it."""

    instance: int


class End(Message):
    """Free every instance and end the worker process (no reply)."""


Request = Open | Run | RunMany | Get | Set | Push | Break | Stop | End
_REQUESTS: dict[str, type[Message]] = {
    c.KIND: c for c in (Open, Run, RunMany, Get, Set, Push, Break, Stop, End)}


def read_request(raw: tuple) -> Request:
    """A request from its wire form (the worker trusts the crslab process).

    >>> read_request(("set", 3, "mycount", None, 2.0))
    Set(instance=3, name='mycount', index=None, value=2.0)
    """
    return _REQUESTS[raw[0]](*raw[1:])  # type: ignore[return-value]


# -- the worker answers -------------------------------------------------------------------------
class MotorBoardEvent(NamedTuple):
    """The motor board cut every output (``off``; ``joint`` 1..3 over the limit, 0 no command) or
    brought them back, at ``tick``."""

    tick: int
    joint: int
    off: bool


class Ready(Message):
    """The worker built the instance's plant and loaded its firmware: ``symbols`` are its
    ``CRS_LAB_HAS_*`` bits."""

    instance: int
    symbols: int


class Failed(Message):
    """The worker could not enter the run sandbox, or open the instance; ``file``: the input file
    to blame (MuJoCo refused the model a world file makes), when it is not the lab."""

    instance: int
    message: str
    file: str = ""


class Trapped(Message):
    """The instance's firmware could not be loaded or stopped in a constructor (``trap``: see
    :func:`crslab.worker.board.trap_info`); the instance is not open."""

    instance: int
    trap: dict


class Ran(Message):
    """A run request's answer: how the chunk ended (a ``CRS_RUN_*`` code), the next tick, the
    board's counters, the motor board's cut-outs starting or ending and what each expectation
    reached saw, since the last reply, and how the firmware stopped when ``code`` is
    ``CRS_RUN_TRAPPED``. The chunk's scope rows are in the instance's shared block
    (crslab/run/shared_block.py), as what it printed is."""

    instance: int
    code: int
    tick: int
    stats: RunStats
    motor_board_events: tuple[MotorBoardEvent, ...]
    observations: tuple[Observation, ...]
    trap: dict | None


class Value(Message):
    """A variable's value (a list for an array), or None: done."""

    value: float | list[float] | None


class Error(Message):
    """The request could not be done (no such watched variable, an index out of range)."""

    message: str


class Stopped(Message):
    """The instance's last counters; it is gone after this."""

    instance: int
    stats: RunStats


Reply = Ready | Failed | Trapped | Ran | Value | Error | Stopped


# -- checking a reply ---------------------------------------------------------------------------
class _Bad(Exception):
    """A field that is not what the reply says it is (its name and why)."""


def _checker(kind: type | tuple[type, ...], said: str) -> Callable[[Any, str], Any]:
    """A check that a reply's field holds a value of ``kind`` (a bool is never a whole number).

    >>> _checker(int, "a whole number")(True, "tick")
    Traceback (most recent call last):
    ...
    crslab.worker.worker_messages._Bad: tick = True, not a whole number
    """

    def check(value: Any, what: str) -> Any:
        if not isinstance(value, kind) or (isinstance(value, bool) and bool not in _types(kind)):
            raise _Bad(f"{what} = {value!r:.40}, not {said}")
        return value

    return check


def _types(kind: type | tuple[type, ...]) -> tuple[type, ...]:
    return kind if isinstance(kind, tuple) else (kind,)


_whole = _checker(int, "a whole number")
_text = _checker(str, "text")
_number = _checker(float, "a number")
_flag = _checker(bool, "a flag")


def _items(value: Any, what: str) -> list | tuple:
    if not isinstance(value, list | tuple):
        raise _Bad(f"{what} is {type(value).__name__}, not a list")
    return value




def _stats(value: Any) -> RunStats:
    """The run's counters (:class:`~crslab.worker.run_stats.RunStats`), every value checked: a
    name crslab does not count, or a value its field does not hold, is :class:`_Bad`."""
    if not isinstance(value, dict):
        raise _Bad(f"stats is {type(value).__name__}, not a table")
    fields = {}
    for key, v in value.items():
        read = _STATS.get(key) if isinstance(key, str) else None
        if read is None:
            raise _Bad(f"stats holds {key!r:.40}, which crslab does not count")
        fields[key] = read(v, f"stats[{key!r}]")
    return RunStats(**fields)


def _trap(value: Any) -> dict:
    """How the firmware stopped (:func:`crslab.worker.main.trap_info`'s fields)."""
    if not isinstance(value, dict):
        raise _Bad(f"trap is {type(value).__name__}, not a table")
    for key in ("kind", "phase", "tick", "exit_code", "line"):
        _whole(value.get(key), f"trap[{key!r}]")
    _text(value.get("text"), "trap['text']")
    return value


def observation(raw: object) -> Observation:
    """An expectation's observation from the worker's reply, checked (the reply is the lab's to
    forge): raises ``ValueError``, ``TypeError`` or ``KeyError`` for anything else.

    >>> observation({"tick": 5, "motor_board": "none", "motor_board_off": 0, "motor_board_cutouts": 0,
    ...              "error": 1, "motor_rad": [0.0, 0.1, 0.2], "var": None}).error
    1
    >>> observation({"tick": 5})
    Traceback (most recent call last):
    ...
    KeyError: 'motor_rad'
    """
    if not isinstance(raw, dict):
        raise TypeError(f"{type(raw).__name__} is not an observation")

    def whole(key: str) -> int:
        value = raw[key]
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"{key} is not a whole number")
        return value

    angles = raw["motor_rad"]
    if not isinstance(angles, list | tuple) or len(angles) != 3 \
            or not all(isinstance(v, float) for v in angles):
        raise TypeError("motor_rad is not three numbers")
    var = raw["var"]
    if var is not None and not isinstance(var, float):
        raise TypeError("var is not a number")
    board = raw["motor_board"]
    if not isinstance(board, str):
        raise TypeError("motor_board is not a name")
    world = raw.get("world")
    if world is not None and (not isinstance(world, dict) or not all(
            isinstance(k, str) and isinstance(v, float) for k, v in world.items())):
        raise TypeError("world is not named numbers")
    return Observation(tick=whole("tick"), motor_board=board, motor_board_off=bool(whole("motor_board_off")),
                       motor_board_cutouts=whole("motor_board_cutouts"), error=whole("error"),
                       motor_rad=(angles[0], angles[1], angles[2]), var=var, world=world)


def _event(raw: Any) -> MotorBoardEvent:
    items = _items(raw, "a motor-board event")
    if len(items) != 3:
        raise _Bad("a motor-board event is not (tick, joint, off)")
    return MotorBoardEvent(_whole(items[0], "its tick"), _whole(items[1], "its joint"),
                           bool(_whole(items[2], "its off")))


def _observations(raw: Any) -> tuple[Observation, ...]:
    try:
        return tuple(observation(o) for o in _items(raw, "observations"))
    except (TypeError, KeyError, ValueError) as exc:
        raise _Bad(f"an observation crslab cannot read ({exc})") from None


def _value(raw: Any) -> float | list[float] | None:
    if raw is None or isinstance(raw, float):
        return raw
    return [_number(v, "value[...]") for v in _items(raw, "value")]


def _instance(value: Any) -> int:
    return _whole(value, "instance")


_STATS = {
    **{name: _whole for name in BOARD_COUNTERS},
    "tick": _whole, "native": _flag, "motor_board": _text, "motor_board_cutouts": _whole,
    "serial_dropped": _whole, "lab_symbols": _whole,
    "first_over_tick": lambda v, what: tuple(_whole(t, f"{what}[...]") for t in _items(v, what)),
    "motor_board_events": lambda v, what: tuple(tuple(_event(e)) for e in _items(v, what)),
}
"""How each field of :class:`~crslab.worker.run_stats.RunStats` is read off the pipe."""

_FIELDS: dict[type[Message], tuple] = {
    Ready: (_instance, lambda v: _whole(v, "symbols")),
    Failed: (_instance, lambda v: _text(v, "message"), lambda v: _text(v, "file")),
    Trapped: (_instance, _trap),
    Ran: (_instance, lambda v: _whole(v, "code"), lambda v: _whole(v, "tick"), _stats,
          lambda v: tuple(_event(e) for e in _items(v, "motor_board_events")), _observations,
          lambda v: None if v is None else _trap(v)),
    Value: (_value,),
    Error: (lambda v: _text(v, "message"),),
    Stopped: (_instance, _stats),
}
"""How each reply's fields are read, in order: each raises :class:`_Bad` for what it is not."""


def _trusted_stats(value: dict) -> RunStats:
    """A trusted reply's counters, typed as they were sent: :meth:`RunStats.wire`'s table of every
    field, taken as it is (not through ``__init__``'s keywords: a server reads some 400 a second).

    >>> stats = RunStats(lab_calls=3, first_over_tick=(4100,), motor_board_events=((4600, 1, True),))
    >>> _trusted_stats(stats.wire()) == stats
    True
    """
    stats = object.__new__(RunStats)
    fields = stats.__dict__
    fields.update(value)
    fields["first_over_tick"] = tuple(value["first_over_tick"])
    fields["motor_board_events"] = tuple((t, j, bool(off)) for t, j, off in value["motor_board_events"])
    return stats


def _trusted_counts(value: tuple | dict) -> RunStats:
    """A trusted ``Ran``'s counters: a WebAssembly worker's row (:meth:`RunStats.row`), or the table
    :meth:`RunStats.wire` makes (a native worker's form, read as trusted by a test).

    >>> stats = RunStats(lab_calls=3, first_over_tick=(4100,))
    >>> _trusted_counts(stats.row()) == _trusted_counts(stats.wire()) == stats
    True
    """
    return RunStats.from_row(value) if type(value) is tuple else _trusted_stats(value)


_TYPED: dict[type[Message], dict[int, Any]] = {
    Ran: {3: _trusted_counts,
          4: lambda v: tuple(MotorBoardEvent(e[0], e[1], bool(e[2])) for e in v),
          5: lambda v: tuple(observation(o) for o in v)},
    Stopped: {1: _trusted_stats},
}
"""A trusted reply's fields that travel as plain data but are read back typed (by position)."""


def _trusted_ran(raw: tuple, instance: int | None) -> Ran:
    """:func:`read_reply` of a trusted ``ran`` reply (its fields taken as they are, its instance
    checked), made as ``Ran(...)`` makes it, without a frozen dataclass's ``__setattr__`` calls.

    >>> ran = Ran(2, 0, 250, RunStats(tick=250), (), (), None)
    >>> read_reply(ran.wire(), Ran, instance=2, trusted=True) == ran
    True
    """
    if instance is not None and raw[1] != instance:
        raise UnreadableReply(f"its ran reply is about instance {raw[1]}, not {instance}")
    typed = _TYPED[Ran]
    reply = object.__new__(Ran)
    reply.__dict__.update(instance=raw[1], code=raw[2], tick=raw[3], stats=typed[3](raw[4]),
                          motor_board_events=typed[4](raw[5]) if raw[5] else (),
                          observations=typed[5](raw[6]) if raw[6] else (), trap=raw[7])
    return reply


def read_reply(raw: object, *due: type[Message], instance: int | None = None, trusted: bool = False) -> Any:
    """The reply ``raw`` (as unpickled) as one of the classes ``due``, every field checked, about
    ``instance`` when given (a reply that names an instance must name that one); raises
    :class:`~crslab.worker.worker_reply.UnreadableReply` for anything else. ``trusted``: a
    WebAssembly worker's reply (no lab code runs in its address space): its kind, its length and
    its instance are checked, its fields taken as they are.

    >>> read_reply(("ready", 0, 3), Ready, Failed, Trapped, instance=0)
    Ready(instance=0, symbols=3)
    >>> read_reply(("ready", 1, 3), Ready, instance=0)
    Traceback (most recent call last):
    ...
    crslab.worker.worker_reply.UnreadableReply: its ready reply is about instance 1, not 0
    >>> read_reply(("value", 1.5), Ran)
    Traceback (most recent call last):
    ...
    crslab.worker.worker_reply.UnreadableReply: it sent a value reply where ran was due
    """
    if trusted and type(raw) is tuple and len(raw) == 8 and raw[0] == "ran" and due[0] is Ran:
        return _trusted_ran(raw, instance)  # a WebAssembly worker's chunk: some 400 a second
    kinds = {c.KIND: c for c in due}
    if not isinstance(raw, tuple) or not raw or not isinstance(raw[0], str):
        raise UnreadableReply(f"it sent {type(raw).__name__} where {due[0].KIND} was due")
    cls = kinds.get(raw[0])
    if cls is None:
        raise UnreadableReply(f"it sent a {raw[0]:.20} reply where {due[0].KIND} was due")
    readers = _FIELDS[cls]
    if len(raw) != 1 + len(readers):
        raise UnreadableReply(f"its {cls.KIND} reply has {len(raw) - 1} fields, not {len(readers)}")
    if trusted:
        typed = _TYPED.get(cls, {})
        reply = cls(*(typed[i](v) if i in typed else v for i, v in enumerate(raw[1:])))
    else:
        try:
            reply = cls(*(read(v) for read, v in zip(readers, raw[1:], strict=True)))
        except _Bad as exc:
            raise UnreadableReply(f"its {cls.KIND} reply holds {exc}") from None
    about = getattr(reply, "instance", instance)
    if instance is not None and about != instance:
        raise UnreadableReply(f"its {cls.KIND} reply is about instance {about}, not {instance}")
    return reply
