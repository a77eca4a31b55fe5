"""A run host (crslab/serve/run_host.py): many pages' runs as instances of one board worker, each
run as ``crslab sim`` runs it, one page's stop ending its run only."""

from __future__ import annotations

import json
import pickle
import threading
from multiprocessing import Pipe
from pathlib import Path

import pytest
from waiting import GUARD_S, wait_until

from crslab._bindings import constants
from crslab.run.api import make_config, simulate
from crslab.run.board_client import BoardClient
from crslab.serve.run_host import HostedRun, RunHost
from crslab.serve.wire import CLOSE, PAGE, RUN, unhost_frame
from crslab.starters import starter_text
from crslab.worker.share import HOST_SHARE, Share

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
    worker = BoardClient(share=HOST_SHARE)  # (forked before the pipe: it holds no end of it, as in a server)
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
    worker = BoardClient(share=HOST_SHARE)  # (forked before the pipe: it holds no end of it, as in a server)
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


# -- runs that share the host's worker (crslab/worker/share.py) ----------------------------------------
SHARING = LABS / "sharing"


def start_host(tmp_path: Path, runs: dict[str, tuple[Path, float | None, int]], **host_options: object
               ) -> tuple[RunHost, object, threading.Thread]:
    """A host (a thread of the test's) given ``runs`` (key: lab, speed, end tick), each with no
    startup delay, on a worker of its own forked before the pipe exists (as in a server): the host,
    the server's end of its pipe, and the thread serving it."""
    worker = BoardClient(share=host_options.get("share", HOST_SHARE))  # type: ignore[arg-type]
    ours, theirs = Pipe()
    host = RunHost(theirs, **host_options)  # type: ignore[arg-type]
    host.worker = worker
    for key, (lab, speed, end_tick) in runs.items():
        folder = tmp_path / key
        (folder / "out").mkdir(parents=True)
        config = make_config(lab, "tour", log=True, startup_delay=False)
        ours.send((RUN, key, pickle.dumps(HostedRun(config, end_tick, speed, 0.5, (), folder))))
    serving = threading.Thread(target=host.serve)
    serving.start()
    return host, ours, serving


def receive(ours: object) -> tuple[str, dict]:
    """The next page message of the host's: its session key and the message."""
    assert ours.poll(GUARD_S), "the host sent nothing"  # type: ignore[attr-defined]
    key, _tag, body = unhost_frame(ours.recv_bytes())  # type: ignore[attr-defined]
    return key, json.loads(body)


def test_a_course_lab_beside_a_slow_lab_and_an_iovec_flood_runs_as_it_runs_alone(tmp_path):
    """A course lab at real time beside a lab that costs more than real time at the speed its page
    asks for (some 9 million instructions a call, 60 ms of the board's; some 0.5 ms of this
    machine's, so at 10x real time it cannot keep its pace) and the 65,000-iovec lab (1000 writev
    a call, 65 million iovecs the board would walk): the course lab runs to its end and prints what
    it prints alone; the slow lab's chunks end at its share (each far shorter than a page's 250
    ticks), its page is told once why it goes slower than asked, and Stop ends it where it was; the
    flood ends at its first call, its line saying the instructions it passed and what the board
    would need."""
    template = tmp_path / "lab1.c"
    template.write_text(starter_text("lab1", "A"))
    flood = tmp_path / "iovec_flood.c"
    flood.write_text((SHARING / "iovec_flood.c").read_text().replace("writes_each_call = 100;",
                                                                     "writes_each_call = 1000;"))
    runs = {"course": (template, 1.0, 3000), "slow": (SHARING / "slow_every_call.c", 10.0, 60_000),
            "flood": (flood, 1.0, 3000)}
    host, ours, serving = start_host(tmp_path, runs)
    messages: dict[str, list[dict]] = {key: [] for key in runs}
    try:
        while not all(m and m[-1]["type"] == "ended" for m in messages.values()):
            key, msg = receive(ours)
            messages[key].append(msg)
            chunks = [m for m in messages["slow"] if m["type"] == "chunk"]
            if key == "slow" and msg["type"] == "chunk" and len(chunks) == 5:
                ours.send((PAGE, "slow", {"type": "stop"}))
    finally:
        ours.close()
        serving.join(30)
    assert not serving.is_alive()

    course = messages["course"][-1]
    alone = simulate(template, "tour", duration_s=3.0, startup_delay=False)
    assert (course["status"], course["end_tick"]) == ("ok", 3000)
    assert (tmp_path / "course" / "out" / "transcript.txt").read_bytes() == alone.transcript

    slow_chunks = [m for m in messages["slow"] if m["type"] == "chunk"]
    assert all(m["tick"] - m["first"] < 100 for m in slow_chunks), [(m["first"], m["tick"])
                                                                    for m in slow_chunks]
    notes = [m for m in messages["slow"] if m["type"] == "note"]
    assert len(notes) == 1 and notes[0]["tick"] == slow_chunks[0]["tick"]  # said after its first chunk
    # what its calls of that chunk cost on average, as the same lab alone counts them
    first = simulate(SHARING / "slow_every_call.c", "tour", duration_s=notes[0]["tick"] / 1000,
                     startup_delay=False)
    cost = first.stats.lab_cost_total / first.stats.lab_calls
    assert notes[0]["text"].startswith(
        f"slow_every_call.c's lab() costs {cost:,.0f} instructions a call: the F28335 would need ")
    assert notes[0]["text"].endswith(
        "; the run goes on slower than 10x real time, so that the server's other runs keep theirs")
    slow = messages["slow"][-1]
    assert (slow["status"], slow["end_tick"]) == ("interrupted", slow_chunks[-1]["tick"])
    assert slow["message"] == f"stopped at t = {slow_chunks[-1]['tick'] / 1000:.3f} s"

    ended = messages["flood"][-1]
    assert (ended["status"], ended["end_tick"]) == ("hung", 0)
    assert ended["message"].startswith("iovec_flood.c is too slow for a shared server: lab() cost more than "
                                       "15,000,000 instructions in one call at tick 0 (t = 0.000 s)")
    assert "the F28335 would need more than 100 ms for that call" in ended["message"]


@pytest.mark.parametrize("how", ["stop", "close"])
def test_stop_or_a_closed_page_ends_a_call_that_would_never_return(tmp_path, how):
    """A lab whose 301st call never returns, on a host whose runs have no deadline and 10 s of CPU
    for one call: only the page's Stop, or its closing, can end that call before then. It ends at
    once, and the host's last word on it is that it was stopped where it was (a host that only
    read the server once its worker was done would end it 10 s of CPU later as too slow)."""
    template = tmp_path / "lab1.c"
    template.write_text(starter_text("lab1", "A"))
    share = Share(chunk_s=0.01, call_s=10.0, call_instructions=0)
    runs = {"spins": (SHARING / "spins_in_lab.c", None, 5000), "course": (template, None, 20_000)}
    host, ours, serving = start_host(tmp_path, runs, share=share, deadline_s=None)
    c = constants
    messages: dict[str, list[dict]] = {key: [] for key in runs}
    try:
        wait_until(lambda: "spins" in host.sessions, "the spinning lab's run opened")
        block = host.sessions["spins"].sim.block  # type: ignore[union-attr]
        wait_until(lambda: block.tick == 300 and block.phase == c.CRS_PHASE_LAB, "the lab spinning")
        ours.send((PAGE, "spins", {"type": "stop"}) if how == "stop" else (CLOSE, "spins"))
        while not messages["course"] or messages["course"][-1]["type"] != "ended":
            key, msg = receive(ours)
            messages[key].append(msg)
    finally:
        ours.close()
        serving.join(30)
    assert not serving.is_alive()
    assert messages["course"][-1]["status"] == "ok"
    # (after a close the server drops this: the run's page is gone)
    assert messages["spins"][-1] == messages["spins"][-1] | {
        "type": "ended", "status": "interrupted", "end_tick": 300, "message": "stopped at t = 0.300 s"}


def test_a_contest_run_whose_chunks_are_cut_ends_where_crslab_contest_ends_it(tmp_path):
    """A contest run at as fast as possible on a host whose share cuts its chunks every few ms of
    CPU (anywhere, not at the page's 1000 ticks): it looks at the arm's motion only where
    ``crslab contest`` looks (every CHUNK_TICKS), so it ends at the same tick, and none of its
    chunks crosses such a tick."""
    from crslab.contest.offsets import contest_rest
    from crslab.contest.run import CHUNK_TICKS, CONTEST_SCENARIO, contest_config, run_contest
    from crslab.world import load_world

    text = starter_text("final", "B")
    lab = tmp_path / "final.c"
    lab.write_text(text)
    rest = contest_rest(text, None)
    config = contest_config(make_config(lab, CONTEST_SCENARIO, world=load_world("contest")), rest)
    alone = run_contest(config)
    assert alone.status == "ok" and alone.end_tick % CHUNK_TICKS == 0 and alone.end_tick < 60_000

    share = Share(chunk_s=0.001, call_s=HOST_SHARE.call_s, call_instructions=HOST_SHARE.call_instructions)
    worker = BoardClient(share=share)
    ours, theirs = Pipe()
    host = RunHost(theirs, share=share)
    host.worker = worker
    (tmp_path / "page" / "out").mkdir(parents=True)
    ours.send((RUN, "page", pickle.dumps(HostedRun(config, 60_000, None, 0.5, (), tmp_path / "page",
                                                   contest=rest, until_still=True))))
    serving = threading.Thread(target=host.serve)
    serving.start()
    got: list[dict] = []
    try:
        while not got or got[-1]["type"] != "ended":
            got.append(receive(ours)[1])
    finally:
        ours.close()
        serving.join(30)
    chunks = [m for m in got if m["type"] == "chunk"]
    assert any(m["tick"] % CHUNK_TICKS for m in chunks)  # cut at its share, off the 1000s
    assert all(m["first"] // CHUNK_TICKS == (m["tick"] - 1) // CHUNK_TICKS
               for m in chunks if m["tick"] > m["first"])
    assert (got[-1]["status"], got[-1]["end_tick"]) == ("ok", alone.end_tick)
