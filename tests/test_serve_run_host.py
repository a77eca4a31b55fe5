"""A run host (crslab/serve/run_host.py): many pages' runs as instances of one board worker, each
run as ``crslab sim`` runs it, one page's stop ending its run only."""

from __future__ import annotations

import json
import pickle
import threading
from multiprocessing import Pipe
from pathlib import Path

from waiting import GUARD_S

from crslab.run.api import make_config, simulate
from crslab.run.board_client import BoardClient
from crslab.serve.run_host import HostedRun, RunHost
from crslab.serve.wire import CLOSE, PAGE, RUN, unhost_frame
from crslab.starters import starter_text

LABS = Path(__file__).parent / "labs"
END_TICK = 3000


class Recorded(RunHost):
    """A host that notes the worker each run was opened in."""

    def __init__(self, conn) -> None:  # noqa: ANN001
        super().__init__(conn)
        self.workers: list[int] = []

    def simulation(self, config, limits):  # noqa: ANN001, ANN201
        sim = super().simulation(config, limits)
        self.workers.append(sim.board_client.pid)
        return sim


def test_a_host_runs_many_pages_labs_in_one_worker_as_crslab_sim_runs_them(tmp_path):
    template = tmp_path / "lab1.c"
    template.write_text(starter_text("lab1", "A"))
    labs = {"a": template, "b": template, "trap": LABS / "faulty" / "stack_overflow_in_lab.c",
            "stopped": template}
    worker = BoardClient()  # (forked before the pipe exists: it holds no end of it, as in a server)
    ours, theirs = Pipe()
    host = Recorded(theirs)
    host.worker = worker
    for key, lab in labs.items():
        folder = tmp_path / key
        (folder / "out").mkdir(parents=True)
        config = make_config(lab, "tour", log=True, startup_delay=False)
        run = HostedRun(config, END_TICK, 1.0 if key == "stopped" else None, 0.5, (), folder)
        ours.send((RUN, key, pickle.dumps(run)))
    serving = threading.Thread(target=host.serve)
    serving.start()
    messages: dict[str, list[dict]] = {key: [] for key in labs}
    ended = 0
    while ended < len(labs):
        key, _tag, body = unhost_frame(ours.recv_bytes())
        msg = json.loads(body)
        messages[key].append(msg)
        if key == "stopped" and msg["type"] == "chunk" and len(messages[key]) == 2:  # started, chunk
            ours.send((PAGE, key, {"type": "stop"}))  # long before its next chunk is due
        ended += msg["type"] == "ended"
    ours.send((CLOSE, "gone"))  # (a page that is not there: nothing happens)
    ours.close()  # the server went: the host closes its runs and its worker
    serving.join(30)
    assert not serving.is_alive()
    assert len(set(host.workers)) == 1 and len(host.workers) == len(labs)  # one worker, every run in it
    assert not host.worker.alive

    for key in ("a", "b", "trap"):
        sim = simulate(labs[key], "tour", duration_s=END_TICK / 1000, startup_delay=False)
        end = messages[key][-1]
        assert (end["type"], end["status"], end["end_tick"]) == ("ended", sim.status.value, sim.end_tick)
        assert end["message"] == sim.message
        assert (tmp_path / key / "out" / "transcript.txt").read_bytes() == sim.transcript
        shown = "".join(text for m in messages[key] if m["type"] == "chunk" for _, text in m["serial"])
        assert shown.encode("latin-1") == sim.transcript
    assert messages["trap"][-1]["status"] != "ok"
    stopped = messages["stopped"][-1]
    first_chunk = next(m for m in messages["stopped"] if m["type"] == "chunk")
    assert stopped["status"] == "interrupted" and stopped["end_tick"] == first_chunk["tick"]
    assert stopped["message"] == f"stopped at t = {first_chunk['tick'] / 1000:.3f} s"


def test_a_recorder_writing_its_files_holds_no_other_run_back(tmp_path, monkeypatch):
    """A recording run's sinks close in a thread of the host's: while its recorder is held in its
    close (until the run beside it has had four more chunks), a run at real time beside it goes on
    getting its chunks, and the recording's ``ended`` comes once its files are written, naming
    them. (Were the close done by the host itself, no chunk would come while it is held: the test
    would fail at the guard.)"""
    from crslab.sinks import rerun_writer

    closing, release = threading.Event(), threading.Event()
    close_files = rerun_writer.RecorderSink.close

    def close(self):  # noqa: ANN001, ANN202
        closing.set()
        assert release.wait(GUARD_S), "the test never let the recorder go on"
        close_files(self)

    monkeypatch.setattr(rerun_writer.RecorderSink, "close", close)
    template = tmp_path / "lab1.c"
    template.write_text(starter_text("lab1", "A"))
    config = make_config(template, "tour", log=True, startup_delay=False)
    worker = BoardClient()  # (forked before the pipe exists: it holds no end of it, as in a server)
    ours, theirs = Pipe()
    host = RunHost(theirs)
    host.worker = worker
    for key, speed, ticks, record in (("live", 1.0, 4000, False), ("rec", None, 500, True)):
        folder = tmp_path / key
        (folder / "out").mkdir(parents=True)
        run = HostedRun(config, ticks, speed, 0.5, (), folder, record_csv=record)
        ours.send((RUN, key, pickle.dumps(run)))
    serving = threading.Thread(target=host.serve)
    serving.start()
    seen: list[tuple[str, dict, bool]] = []  # (page, message, whether the recorder was held then)
    try:
        while not any(key == "live" and m["type"] == "ended" for key, m, _ in seen):
            sent = [(k, m["type"]) for k, m, _ in seen]
            assert ours.poll(GUARD_S), f"no message from the host; it had sent {sent}"
            key, _tag, body = unhost_frame(ours.recv_bytes())
            held = closing.is_set() and not release.is_set()
            seen.append((key, json.loads(body), held))
            if held and sum(1 for k, m, h in seen if h and k == "live" and m["type"] == "chunk") >= 4:
                release.set()
    finally:
        release.set()
        ours.close()
        serving.join(30)
    assert not serving.is_alive()
    rec_ended = next(i for i, (k, m, _) in enumerate(seen) if k == "rec" and m["type"] == "ended")
    live_while_held = [i for i, (k, m, h) in enumerate(seen) if h and k == "live" and m["type"] == "chunk"]
    assert len(live_while_held) == 4 and max(live_while_held) < rec_ended  # before the recording ended
    assert seen[rec_ended][1]["status"] == "ok" and seen[rec_ended][1]["downloads"] == ["transcript", "csv"]
    rows = (tmp_path / "rec" / "out" / "run.csv").read_text().splitlines()
    assert len(rows) == 1 + 500  # every tick: a recording run's board logs them all
