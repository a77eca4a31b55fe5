"""The messages between crslab and its worker (crslab/worker/worker_messages.py): every message travels as
plain data and reads back as itself; a reply that is not the one due, or holds a field of the wrong
kind, is one UnreadableReply naming it (a native lab may write anything into the pipe)."""

import dataclasses
import pickle

import pytest

from crslab.scenario.expect_events import Observation
from crslab.worker import worker_messages
from crslab.worker.run_stats import RunStats
from crslab.worker.worker_messages import (
    Break,
    End,
    Error,
    Failed,
    Get,
    MotorBoardEvent,
    Open,
    Push,
    Ran,
    Ready,
    Run,
    RunMany,
    Set,
    Stop,
    Stopped,
    Trapped,
    Value,
    read_reply,
    read_request,
)
from crslab.worker.worker_reply import UnreadableReply

TRAP = {"kind": 3, "phase": 1, "tick": 5123, "exit_code": 0, "line": 27, "text": "open /x for reading"}
OBSERVATION = Observation(tick=4200, motor_board="piccolo", motor_board_off=True, motor_board_cutouts=1,
                          error=0, motor_rad=(0.0, -0.42, 0.24), var=1.5)
REPLIES = [
    Ready(instance=0, symbols=7),
    Failed(instance=0, message="Landlock is not available"),
    Trapped(instance=3, trap=TRAP),
    Ran(instance=0, code=0, tick=5000,
        stats=RunStats(over_budget=2, first_over_tick=(4100, 4200), cost_unit=1, native=True,
                       motor_board="piccolo", motor_board_events=((4500, 2, True),)),
        motor_board_events=(MotorBoardEvent(4500, 2, True), MotorBoardEvent(4800, 0, False)),
        observations=(OBSERVATION,), trap=None),
    Ran(instance=12, code=3, tick=5123, stats=RunStats(), motor_board_events=(), observations=(), trap=TRAP),
    Value(value=1.5),
    Value(value=[1.0, 2.5]),
    Value(value=None),
    Error(message="no watched variable Kp"),
    Stopped(instance=0, stats=RunStats(tick=5000, lab_calls=900)),
]
REQUESTS = [Run(0, 5000), RunMany([[0, 5000], [4, 4200]]), Get(0, "mycount"), Set(2, "Kp", None, 2.0),
            Set(0, "gains", 1, 0.5), Push(0, [[0.0] * 6, [1.0, 0, 0, 0, 0, 0]]), Break(0), Stop(7), End(),
            Open(5, None, 2.0)]


@pytest.mark.parametrize("reply", REPLIES, ids=lambda r: r.KIND)
def test_each_reply_reads_back_as_itself_after_the_pipe(reply):
    wire = pickle.loads(pickle.dumps(reply.wire()))
    assert wire[0] == reply.KIND and all(not dataclasses.is_dataclass(v) for v in wire[1:])
    assert read_reply(wire, type(reply)) == reply


@pytest.mark.parametrize("request_", REQUESTS, ids=lambda r: r.KIND)
def test_each_request_reads_back_as_itself(request_):
    assert read_request(pickle.loads(pickle.dumps(request_.wire()))) == request_


def test_every_reply_has_a_reader_for_each_of_its_fields():
    for cls in (Ready, Failed, Trapped, Ran, Value, Error, Stopped):
        assert len(worker_messages._FIELDS[cls]) == len(dataclasses.fields(cls)), cls.KIND
    assert set(worker_messages._STATS) == {f.name for f in dataclasses.fields(RunStats)}


def test_run_statistics_read_back_typed_from_the_pipe():
    stats = RunStats(lab_calls=900, first_over_tick=(4100, 4200), native=True, motor_board="piccolo",
                     motor_board_events=((4600, 1, True), (6100, 1, False)))
    back = read_reply(pickle.loads(pickle.dumps(Stopped(0, stats).wire())), Stopped).stats
    assert back == stats and back.lab_calls == 900 and back.nan_first_tick == -1
    assert back.motor_board_events[0] == (4600, 1, True) and back.motor_board_events[1][2] is False


@pytest.mark.parametrize(("raw", "due", "words"), [
    ("ran", Ran, "it sent str where ran was due"),
    (("value", 1.5), Ran, "it sent a value reply where ran was due"),
    (("ran", 0, 0, 5000, {}), Ran, "its ran reply has 4 fields, not 7"),
    (("ran", 0, 0, True, {}, [], [], None), Ran, "tick = True, not a whole number"),
    (("ran", 0, 0, 5000, {"x": object()}, [], [], None), Ran, "stats holds 'x', which crslab does not"),
    (("ran", 0, 0, 5000, {"lab_calls": "9"}, [], [], None), Ran, r"\['lab_calls'\] = '9', not a whole"),
    (("ran", 0, 0, 5000, {"native": 1}, [], [], None), Ran, r"stats\['native'\] = 1, not a flag"),
    (("ran", 0, 0, 5000, {"first_over_tick": [1.5]}, [], [], None), Ran, r"first_over_tick'\]\[...\]"),
    (("ran", 0, 0, 5000, {}, [(1, 2)], [], None), Ran, r"not \(tick, joint, off\)"),
    (("ran", 0, 0, 5000, {}, [], [{"tick": 1}], None), Ran, "an observation crslab cannot read"),
    (("ran", 1, 0, 5000, {}, [], [], None), Ran, "its ran reply is about instance 1, not 0"),
    (("ran", "0", 0, 5000, {}, [], [], None), Ran, "instance = '0', not a whole number"),
    (("trapped", 0, {**TRAP, "line": "27"}), Trapped, r"trap\['line'\]"),
    (("value", ["1.0"]), Value, r"value\[...\] = '1.0', not a number"),
    (("ready", 0, 1, 2), Ready, "its ready reply has 3 fields, not 2"),
])
def test_a_reply_that_is_not_the_one_due_is_one_line(raw, due, words):
    with pytest.raises(UnreadableReply, match=words):
        read_reply(raw, due, instance=0)
