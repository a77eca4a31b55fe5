"""Sinks: one interface, a fan-out that feeds many and closes them all, a threaded wrapper that
keeps the order of calls."""

import threading

import numpy as np
import pytest

from crslab.sinks.memory import MemorySink
from crslab.sinks.sink import FanOut, Sink, SinkError
from crslab.sinks.stdout import StdoutSink
from crslab.sinks.threaded import ThreadedSink
from crslab.sinks.transcript_file import TranscriptSink


class Recorder(Sink):
    def __init__(self, name, events, fail=None):
        self.name, self.events, self.fail = name, events, fail

    def on_serial(self, tick, data):
        self.events.append((self.name, "serial", tick))

    def on_log(self, columns):
        self.events.append((self.name, "log", int(columns["tick"][-1, 0])))

    def flush(self):
        self.events.append((self.name, "flush"))

    def close(self):
        self.events.append((self.name, "close"))
        if self.fail is not None:
            raise self.fail


def test_a_fan_out_hands_every_call_to_each_sink_in_order():
    events = []
    out = FanOut([Recorder("a", events)])
    out.add(Recorder("b", events))
    out.on_serial(4100, b"x")
    out.on_log({"tick": np.array([[4100]])})
    out.flush()
    out.close()
    assert events == [("a", "serial", 4100), ("b", "serial", 4100), ("a", "log", 4100), ("b", "log", 4100),
                      ("a", "flush"), ("b", "flush"), ("a", "close"), ("b", "close")]


def test_closing_a_fan_out_closes_every_sink_and_names_each_file_that_failed():
    events = []
    full = OSError(28, "No space left on device", "run.csv")
    gone = OSError(2, "No such file or directory", "run.rrd")
    out = FanOut([Recorder("a", events, fail=full), Recorder("b", events), Recorder("c", events, fail=gone)])
    with pytest.raises(SinkError) as err:
        out.close()
    assert [e for e in events if e[1] == "close"] == [("a", "close"), ("b", "close"), ("c", "close")]
    assert str(err.value) == ("could not finish writing run.csv: No space left on device; "
                              "run.rrd: No such file or directory")


def test_another_error_while_closing_is_raised_once_every_sink_is_closed():
    events = []
    out = FanOut([Recorder("a", events, fail=ValueError("bad rows")), Recorder("b", events)])
    with pytest.raises(ValueError, match="bad rows"):
        out.close()
    assert ("b", "close") in events


def test_a_threaded_sink_keeps_the_order_of_calls_and_works_off_the_callers_thread():
    seen = []

    class Slow(MemorySink):
        def on_serial(self, tick, data):
            seen.append(threading.current_thread().name)
            super().on_serial(tick, data)

        def flush(self):
            self.sent.append((-1, b"flush"))

    inner = Slow()
    sink = ThreadedSink(inner, depth=2)
    for tick in range(50):
        sink.on_serial(tick, bytes([65 + tick % 26]))
        if tick % 10 == 9:
            sink.flush()
    sink.close()
    assert [t for t, _ in inner.sent if t >= 0] == list(range(50))
    assert [i for i, (t, _) in enumerate(inner.sent) if t < 0] == [10, 21, 32, 43, 54]
    assert set(seen) == {"crslab-sink"}


def test_a_threaded_sink_s_queue_holds_only_the_calls_its_sink_takes():
    # a CSV-like sink busy with a chunk's rows: the run's other calls of a chunk (which the sink
    # does not take) must not fill the queue and hold the run until the rows are written (the run
    # then asked the worker for its next chunk only after the CSV was written: no overlap)
    writing = threading.Event()

    class Rows(Sink):
        def __init__(self):
            self.rows = []

        def on_log(self, columns):
            writing.wait()
            self.rows.append(int(columns["tick"][-1, 0]))

    inner = Rows()
    sink = ThreadedSink(inner, depth=2)

    def run_two_chunks():
        for end in (20_000, 40_000):
            sink.on_print(end, 1)
            sink.on_serial(end, b"x")
            sink.on_log({"tick": np.array([[end]])})
            sink.flush()
            sink.on_reached(end)

    run = threading.Thread(target=run_two_chunks)
    run.start()
    run.join(timeout=10)   # blocked on a full queue it would wait for `writing`, which comes after
    done = not run.is_alive()
    writing.set()
    run.join()
    sink.close()
    assert done and inner.rows == [20_000, 40_000]


def test_stdout_and_transcript_see_the_same_bytes_split_anywhere(tmp_path):
    import io

    stream = io.BytesIO()
    path = tmp_path / "t.txt"
    out = FanOut([StdoutSink(stream), TranscriptSink(path)])
    for tick, data in [(0, b"1.00 2.00\n"), (0, b"\r3.00\n\r"), (5, b"4\r\n")]:
        out.on_serial(tick, data)
    out.flush()
    assert path.read_bytes() == b"1.00 2.00\n\r3.00\n\r4\r\n"  # flushed: on disk before the end
    out.close()
    assert stream.getvalue() == b"1.00 2.00\n3.00\n4\n"


class EndWatcher(Sink):
    """Notes every call of a run, to see where ``on_end`` comes."""

    def __init__(self):
        self.calls: list[str] = []
        self.result = None

    def on_serial(self, tick, data):
        self.calls.append("on_serial")

    def flush(self):
        self.calls.append("flush")

    def on_end(self, result):
        self.calls.append("on_end")
        self.result = result

    def close(self):
        self.calls.append("close")


def test_a_run_ends_with_on_end_once_after_every_byte_with_its_result():
    from crslab.run.api import simulate

    watcher, inner = EndWatcher(), EndWatcher()
    threaded = ThreadedSink(inner)
    result = simulate(None, "hands_off", duration_s=5.0, sinks=[watcher, threaded])
    threaded.close()
    assert result.ok and result.end_tick == 5000 and result.transcript
    assert watcher.calls.count("on_end") == 1 and watcher.calls[-1] == "on_end"  # close is the caller's
    assert "on_serial" in watcher.calls
    assert (watcher.result.status, watcher.result.end_tick, watcher.result.stats) == \
        (result.status, 5000, result.stats)
    assert inner.calls[-2:] == ["on_end", "close"] and inner.calls.count("on_end") == 1
    assert inner.result is watcher.result
