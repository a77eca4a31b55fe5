"""crslab serve's WebSocket protocol and HTTP routes, without a browser: a real server (started as a
user starts it), a page's messages, and what comes back. Each run is compared with what
``crslab sim`` does with the same lab and scenario (``simulate``, the same run from Python)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from serve_server import (
    USERS,
    Client,
    ServeProcess,
    logged_in,
    roster_server,
    run_message,
    serial_of,
    write_roster,
)

from crslab.regress.transcript import read_golden
from crslab.run.api import simulate
from crslab.starters import starter_text

LABS = Path(__file__).parent / "labs"
LAB_A = starter_text("lab1", "A")


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    yield from roster_server(tmp_path_factory)


@pytest.fixture(scope="module")
def alice(server):
    yield from logged_in(server, "alice")


def test_a_run_streams_the_bytes_crslab_sim_prints_at_their_ticks(server, alice, tmp_path):
    lab = tmp_path / "lab.c"
    lab.write_text(LAB_A)
    alice.send(run_message(lab, duration=6.0))
    got = alice.until("ended")
    kinds = [m["type"] for m in got]
    assert kinds[:2] == ["built", "started"] and kinds[-1] == "ended" and got[-1]["status"] == "ok"
    expected = simulate(lab, "tour", duration_s=6.0)
    assert serial_of(got) == expected.sent  # the same bytes, each at the same tick
    assert got[-1]["end_tick"] == 6000
    # the transcript download holds exactly those bytes
    status, _, body = server.request(
        "GET", f"/api/download/transcript?session={alice.hello['session']}", cookie=server.login("alice")
    )
    assert status == 200 and body == expected.transcript


def test_the_run_options_are_crslab_sims(alice, tmp_path):
    """Offsets (the arm's resting motor angles) and no startup delay: the same bytes as
    ``crslab sim --offsets -0.40 0.26 --no-startup-delay``."""
    lab = tmp_path / "lab.c"
    lab.write_text(LAB_A)
    alice.send(run_message(lab, duration=2.0, offsets=[-0.40, 0.26], no_startup_delay=True))
    got = alice.until("ended")
    options = ["--duration", "2", "--offsets", "-0.40", "0.26", "--no-startup-delay", "--fast", "--quiet"]
    sim = subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", str(lab), *options, "--no-stdin",
                          "--transcript", str(tmp_path / "t.txt")], capture_output=True, check=True)
    assert sim.returncode == 0
    text = b"".join(data for _, data in serial_of(got))
    assert text == (tmp_path / "t.txt").read_bytes() and text.startswith(b"0.00 ")  # printed from tick 0
    assert serial_of(got)[0][0] == 0


def test_a_chunk_carries_the_arm_at_60_hz_and_the_scopes_every_5_ms(alice):
    """The scopes have a row every 5 ms (what the course's Simulink model samples); the arm's
    frames are rows too, the first of each 1/60 s of simulated time."""
    alice.send(run_message(LAB_A, duration=2.0, scenario={"name": "hands_off"}))
    got = alice.until("ended")
    chunks = [m for m in got if m["type"] == "chunk"]
    frames = [f for c in chunks for f in c["frames"]]
    ticks = sorted({f[0] for f in frames})
    # a frame starts every 1/60 s of simulated time: ticks 0, 20, 35, 50, 70, 85, ... (and each chunk's last)
    sixty = [t for t in range(0, 2000, 5) if (t * 60) // 1000 != ((t - 5) * 60) // 1000]
    assert len(sixty) == 120 and set(sixty) <= set(ticks) and all(t % 5 == 0 for t in ticks)
    assert len(ticks) <= len(sixty) + len(chunks)
    rows = sum(c["scope"]["rows"] for c in chunks)
    assert rows == 400 and all(c["scope"]["every"] == 5 for c in chunks)
    assert [c["scope"]["tick0"] for c in chunks][:2] == [0, -(-chunks[0]["tick"] // 5) * 5]
    assert chunks[-1]["tick"] == 2000 and all(a["tick"] == b["first"] for a, b in zip(chunks, chunks[1:]))
    # the scope's motor angles are the frames' motor angles at the same tick
    import base64

    first = chunks[0]
    block = np.frombuffer(base64.b64decode(first["scope"]["data"]), "<f4").reshape(first["scope"]["rows"], 13)
    frame0 = first["frames"][0]
    assert frame0[0] == 0 and np.allclose(block[0, 4:7], frame0[4:7], atol=1e-5)


def test_a_chunks_frames_travel_packed_and_unpack_into_the_arms_rows(alice):
    """On the wire a chunk's frames are packed rows (base64 little-endian float64, as the page's
    script unpacks them): each row the tick, the DH angles, the motor angles, the safety flag and the
    motor board's state, equal to what the scope rows say of the same tick."""
    import base64

    alice.send(run_message(LAB_A, duration=1.0, scenario={"name": "hands_off"}))
    raw = []
    while not raw or raw[-1]["type"] != "ended":
        raw.append(json.loads(alice.ws.recv(timeout=120)))
    chunk = next(m for m in raw if m["type"] == "chunk")
    packed = chunk["frames"]
    assert set(packed) == {"columns", "rows", "data"} and packed["columns"] == 9
    rows = np.frombuffer(base64.b64decode(packed["data"]), "<f8").reshape(packed["rows"], 9)
    last = chunk["tick"] - 1 - (chunk["tick"] - 1) % 5  # the last row logged before the chunk's end
    assert rows[0, 0] == 0 and rows[-1, 0] == last
    scope = np.frombuffer(base64.b64decode(chunk["scope"]["data"]), "<f4").reshape(chunk["scope"]["rows"], 13)
    at = {int(t): i for i, t in enumerate(chunk["scope"]["tick0"] + 5 * np.arange(chunk["scope"]["rows"]))}
    for row in rows:
        assert np.allclose(row[4:7], scope[at[int(row[0])], 4:7], atol=1e-6)  # float32 scopes: 1e-7 rad
        assert row[7] in (0, 1) and row[8] in (0, 1)


def test_writing_a_watched_variable_changes_what_the_lab_prints(alice):
    alice.send(run_message(LAB_A, duration=8.0, speed=1.0, no_startup_delay=True))
    first = alice.until("chunk")
    alice.send({"type": "vars", "cmd": "set", "name": "whattoprint", "value": 1})
    alice.send({"type": "vars", "cmd": "get", "name": "whattoprint"})
    replies = []
    got = []
    while len(replies) < 2:
        m = alice.next()
        got.append(m)
        if m["type"] == "vars":
            replies.append(m)
    assert replies[0]["ok"] and replies[0]["reply"].startswith("whattoprint = 1   (from t = ")
    assert replies[1]["values"] == {"whattoprint": "1"}
    while b"I love robotics" not in b"".join(data for _, data in serial_of(got)):
        got.append(alice.next())
    alice.send({"type": "stop"})
    got += alice.until("ended")
    text = b"".join(data for _, data in serial_of(first + got))
    assert text.startswith(b"0.00 ")  # the angles before the write
    assert b"I love robotics\n\r" in text  # the greeting after it
    assert got[-1]["status"] == "interrupted" and got[-1]["message"].startswith("stopped at t = ")


def test_stop_ends_a_real_time_run_within_a_chunk(alice):
    from crslab.run.pacing import PAGE_CHUNKS

    alice.send(run_message(LAB_A, speed=1.0))
    first = alice.until("chunk")[-1]["tick"]
    alice.send({"type": "stop"})
    got = alice.until("ended")
    end = got[-1]["end_tick"]
    assert got[-1]["status"] == "interrupted"
    # the run was paced: stopped within a chunk of when the stop came (not run on to 25 s)
    assert first <= end <= first + PAGE_CHUNKS.realtime_ticks
    assert max((m["tick"] for m in got if m["type"] == "chunk"), default=first) <= end


def test_a_compile_error_names_its_line(alice):
    alice.send(
        {"type": "build", "lab": {"name": "broken.c", "text": (LABS / "does_not_compile.c").read_text()}}
    )
    built = alice.until("built")[-1]
    assert not built["ok"] and built["message"] == "broken.c does not compile"
    assert [d["line"] for d in built["diagnostics"] if d["severity"] == "error"] == [9]
    assert "Kp_gain" in built["diagnostics"][0]["message"]


def test_a_hostile_lab_is_stopped_and_named(alice):
    alice.send(run_message(LABS / "hostile" / "read_file.c", name="read_file.c"))
    ended = alice.until("ended")[-1]
    assert ended["status"] == "forbidden"
    assert "was stopped by the sandbox: it tried to open" in ended["message"]


def test_a_hung_lab_gets_its_diagnosis(alice):
    """A call that never returns, in a run host many pages share, ends at its share of the host
    (docs/serve.md), not at the 2 s deadline of a run with a worker of its own."""
    alice.send(run_message(LABS / "faulty" / "hang_in_lab.c", name="hang.c"))
    ended = alice.until("ended")[-1]
    assert ended["status"] == "hung" and ended["message"].startswith(
        "hang.c is too slow for a shared server: lab() cost more than 15,000,000 instructions in one call "
        "at tick 5123 (t = 5.123 s); it was at hang.c:")


@pytest.mark.parametrize(
    "bad, error",
    [
        ("not json", "not JSON"),
        ('{"type": "launch"}', "unknown message type 'launch'"),
        ('{"type": "run", "lab": {"name": "../x.c", "text": ""}}', "not a plain file name"),
        (
            '{"type": "run", "lab": {"name": "x.c", "text": "int x;"}, "speed": -1}',
            "speed: must be a number > 0",
        ),
        ('{"type": "vars", "cmd": "set", "name": "x"}', "value: must be a number"),
        (
            '{"type": "hand", "body": "forearm", "anchor": [0, 0], "target": [0, 0, 1]}',
            "anchor: must be three",
        ),
        ('{"type": "stop", "now": true}', "stop: unknown field now"),
    ],
)
def test_a_bad_message_gets_one_clear_error_and_nothing_else(alice, bad, error):
    alice.send(bad)
    reply = alice.next()
    assert reply["type"] == "error" and error in reply["message"]
    # nothing else happened: the next answer is the one to the next message
    alice.send({"type": "vars", "cmd": "list"})
    assert alice.next() == {
        "type": "vars",
        "ok": False,
        "cmd": "list",
        "reply": "no run is going on: Run first",
    }


def test_one_run_at_a_time_per_user(server, alice):
    other = Client(server, server.login("alice"))
    try:
        alice.send(run_message(LAB_A, speed=1.0))
        alice.until("started")
        other.send(run_message(LAB_A))
        refused = other.next()
        assert refused["type"] == "error" and "one build, run or check at a time" in refused["message"]
        alice.send({"type": "stop"})
        alice.until("ended")
    finally:
        other.close()


def test_two_users_cannot_see_each_others_sessions(server, alice):
    bob_cookie = server.login("bob")
    session = alice.hello["session"]
    status, _, _ = server.request("GET", f"/api/download/transcript?session={session}", cookie=bob_cookie)
    assert status == 404
    status, _, page = server.request("GET", "/admin", cookie=bob_cookie)
    assert status == 403
    status, _, page = server.request("GET", "/admin", cookie=server.login("ta"))
    assert status == 200 and b"<td>alice</td>" in page and session[:8].encode() in page


def test_a_websocket_needs_a_login_and_the_pages_own_origin(server):
    from websockets.exceptions import ConnectionClosed, InvalidStatus

    for cookie, origin in (("", None), (server.login("bob"), "http://evil.example")):
        with pytest.raises((ConnectionClosed, InvalidStatus)):
            Client(server, cookie, origin=origin)


def test_an_uploaded_scenario_runs_and_a_failed_expectation_is_named(alice):
    scenario = (
        'name = "still"\ndescription = "the arm left alone"\nend = 6.0\n\n'
        '[[event]]\nat = 5.0\nkind = "expect"\nmotor_deg = [0, 90, 0]\nmessage = "not at DH zero"\n'
    )
    alice.send(run_message(LAB_A, scenario={"file": {"name": "still.toml", "text": scenario}}))
    got = alice.until("ended")
    started, ended = got[1], got[-1]
    assert started["scenario"] == "still" and started["events"][0]["tick"] == 5000
    judged = [m for m in got if m["type"] == "expectation"]
    assert [m["met"] for m in judged] == [False]
    assert ended["status"] == "unmet" and ended["message"] == "1 of 1 expectations of scenario still failed"
    assert "not at DH zero" in ended["failed_expectations"][0]


def test_a_malformed_scenario_file_is_one_line_and_nothing_runs(alice):
    alice.send(run_message(LAB_A, scenario={"file": {"name": "bad.toml", "text": "end = \"soon\"\n"}}))
    got = alice.until("ended")
    assert [m["type"] for m in got] == ["built", "ended"]
    assert got[-1]["bad_input"] and "bad.toml" in got[-1]["message"] and "\n" not in got[-1]["message"]


@pytest.mark.parametrize("text, line", [
    ("end = 30\nseed = " + "9" * 400 + "\n", "bad.toml:2: seed: a whole number of 400 digits is too large"),
    ("end = 30\n[[event]]\nat = 1\nkind = \"hand\"\nmotor_deg = " + "[" * 5000 + "\n",
     "bad.toml:5: event.motor_deg: nested too deep"),
    ("end = 1e300\n", "bad.toml:1: end: 1e300 is too large a number"),
    ("end = 30\n[[event]]\nat = 1e-300\nkind = \"estop\"\n",
     "bad.toml:3: event.at: 1e-300 is too small a number"),
])
def test_a_hostile_scenario_file_is_its_line_and_nothing_runs(alice, text, line):
    """Issue 38: a 400-digit integer and deep nesting showed "crslab failed: RecursionError"."""
    alice.send(run_message(LAB_A, scenario={"file": {"name": "bad.toml", "text": text}}))
    got = alice.until("ended")
    assert [m["type"] for m in got] == ["built", "ended"]
    assert got[-1]["bad_input"] and got[-1]["message"].startswith(line), got[-1]["message"]


def test_the_csv_and_the_rrd_of_a_run_can_be_downloaded(server, alice):
    from crslab.scopes.signals import csv_header

    alice.send(run_message(LAB_A, duration=1.0, record={"csv": True, "rrd": True}))
    ended = alice.until("ended")[-1]
    assert ended["status"] == "ok" and ended["downloads"] == ["transcript", "csv", "rrd"]
    cookie = server.login("alice")
    session = alice.hello["session"]
    status, _, body = server.request("GET", f"/api/download/csv?session={session}", cookie=cookie)
    rows = body.decode().splitlines()
    assert status == 200 and rows[0] == ",".join(csv_header()) and len(rows) == 1 + 1000
    assert rows[1].startswith("0,0,") and rows[-1].startswith("999,0.999,")
    status, _, body = server.request("GET", f"/api/download/rrd?session={session}", cookie=cookie)
    assert status == 200 and body[:4] == b"RRF2"  # a rerun recording
    # the session forks the next run's worker safely: rerun's and pyarrow's threads live elsewhere
    alice.send(run_message(LAB_A, duration=1.0))
    assert alice.until("ended")[-1]["status"] == "ok"


def test_limits_compiles_per_minute_and_run_length(tmp_path):
    folder = tmp_path
    srv = ServeProcess(folder, "--users", str(write_roster(folder)), "--compiles-per-minute", "2",
                       "--max-run-s", "1.5")
    try:
        client = Client(srv, srv.login("bob"))
        client.send(run_message(LAB_A))  # the tour is 25 s: cut at 1.5 s
        got = client.until("ended")
        assert got[1]["end_tick"] == 1500 and got[-1]["end_tick"] == 1500
        assert got[1]["notes"] == ["this server runs a lab for at most 1.5 s of simulated time"]
        client.send({"type": "build", "lab": {"name": "lab.c", "text": LAB_A}})
        client.until("built")
        client.send({"type": "build", "lab": {"name": "lab.c", "text": LAB_A}})
        refused = client.next()
        assert refused == {"type": "error", "message": "build: at most 2 compiles a minute; wait a little"}
        client.close()
    finally:
        srv.stop()


def test_a_login_needs_the_right_password(server):
    status, cookies, body = server.request(
        "POST", "/api/login", {"name": "alice", "password": "bob-password"}
    )
    assert status == 401 and not cookies and json.loads(body)["error"] == "wrong name or password"
    assert server.request("GET", "/api/me")[0] == 401


def test_the_hand_pulls_the_forearm_toward_the_mouse(alice):
    """With the arm left alone (hands_off), holding the forearm's tip 15 cm higher raises it: the
    motor angle of joint 3 falls (the forearm turns up)."""
    alice.send(run_message(LAB_A, scenario={"name": "hands_off"}, speed=4.0, duration=8.0))
    got = alice.until("chunk")
    start = got[-1]["frames"][-1]
    tip_local = [0.254, 0.0, 0.0]  # the forearm's far end, 10 in along its x axis (DH frame 3)
    from crslab import crs

    tip = crs.fk(crs.dh_to_motor(np.array(start[1:4]))) * crs.M_PER_IN  # forward kinematics, in m
    alice.send(
        {"type": "hand", "body": "forearm", "anchor": tip_local, "target": (tip + [0, 0, 0.15]).tolist()}
    )
    frames = []
    while not frames or frames[-1][0] < start[0] + 1500:
        m = alice.next()
        frames += m.get("frames", [])
    alice.send({"type": "release"})
    alice.send({"type": "stop"})
    alice.until("ended")
    moved = np.array(frames[-1][4:7]) - np.array(start[4:7])
    assert moved[2] < -0.2  # motor 3 (the forearm's absolute angle) turned it up by > 0.2 rad


def test_check_compares_with_a_golden_file(alice, tmp_path):
    lab = tmp_path / "lab1.c"
    lab.write_text(LAB_A)
    golden = tmp_path / "golden.txt"
    subprocess.run(
        [sys.executable, "-m", "crslab", "record", "--lab", str(lab), "--duration", "6", "-o", str(golden)],
        check=True,
        capture_output=True,
    )
    alice.send({"type": "build", "lab": {"name": "lab1.c", "text": LAB_A}})
    alice.until("built")
    alice.send(
        {"type": "check", "lab": {"name": "lab1.c", "text": LAB_A},
         "golden": {"name": "golden.txt", "text": golden.read_bytes().decode("latin-1")}}
    )
    checked = alice.until("checked")[-1]
    printed = read_golden(golden).body.count(b"\n")  # 12: three lines every 0.5 s from t = 4.5 s
    assert checked["ok"] and checked["report"].startswith(f"match: {printed} lines")
    changed = golden.read_bytes().decode("latin-1").replace("-21.19", "-21.50", 1)
    alice.send({"type": "check", "lab": {"name": "lab1.c", "text": LAB_A},
                "golden": {"name": "golden.txt", "text": changed}})
    checked = alice.until("checked")[-1]
    assert not checked["ok"] and f"mismatch: 1 of {printed} lines differ" in checked["report"]
    alice.send(run_message(LAB_A, duration=1.0))  # the check is over: the next run may start
    assert alice.until("ended")[-1]["status"] == "ok"


def test_serve_refuses_other_hosts_without_a_roster():
    r = subprocess.run(
        [sys.executable, "-m", "crslab", "serve", "--host", "0.0.0.0", "--port", "0"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert r.returncode == 2 and r.stderr.count("\n") == 1
    assert "without --users crslab serve serves only this machine" in r.stderr


def test_a_bad_roster_is_one_line(tmp_path):
    roster = tmp_path / "roster.csv"
    roster.write_text("name,secret\nalice,hunter2\n")
    r = subprocess.run(
        [sys.executable, "-m", "crslab", "serve", "--users", str(roster), "--port", "0"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert r.returncode == 2 and r.stderr.strip().endswith(
        "line 2: alice's secret must be a password hash (crslab serve --hash-password) or token:TOKEN "
        "(at least 8 characters)"
    )


def test_the_local_server_wants_the_token_it_printed(tmp_path):
    srv = ServeProcess(tmp_path)
    try:
        assert "?token=" in srv.url
        status, cookies, _ = srv.request("GET", "/?token=wrong")
        assert status == 200 and not cookies
        status, cookies, _ = srv.request("GET", srv.url.split(srv.host)[1])
        assert status == 303 and "crslab_session" in cookies
        cookie = f"crslab_session={cookies['crslab_session']}"
        assert json.loads(srv.request("GET", "/api/me", cookie=cookie)[2])["user"] == "you"
    finally:
        srv.stop()


def test_hash_password_makes_a_roster_hash():
    r = subprocess.run(
        [sys.executable, "-m", "crslab", "serve", "--hash-password"],
        input="long enough\n",
        capture_output=True,
        text=True,
        check=True,
    )
    from crslab.serve.auth import verify_secret

    assert verify_secret(r.stdout.strip(), "long enough") and not verify_secret(
        r.stdout.strip(), "long enougH"
    )


assert set(USERS) == {"alice", "bob", "ta"}


def test_letting_go_takes_the_hands_force_away_once():
    """The page's control between two chunks: a hand pushes the grabbed link toward the mouse (a
    force on that body only, toward the target), a release pushes zero once, then nothing."""
    from crslab.live.console import VarConsole
    from crslab.run.pacing import PAGE_CHUNKS, Pacer
    from crslab.serve.stream import PageControl
    from crslab.sinks.page_stream import ArmPoses, BrowserStream

    class Lab:
        tick = 100
        pushes: list = []

        def push(self, forces):
            self.pushes.append(np.array(forces))

    arm = ArmPoses()
    stream = BrowserStream(lambda data: None, arm)
    stream.pose.qpos_dh_rad = np.array([0.0, -np.pi / 2, np.pi / 2])  # motor zero: the forearm level
    control = PageControl(lambda data: None, stream, VarConsole(()), Pacer(None, chunks=PAGE_CHUNKS),
                          lambda msg: None)
    lab = Lab()
    # the forearm's tip is at x y z = 10 0 20 in (0.254 0 0.508 m); the mouse holds it 0.2 m higher
    control.command(lab, {"type": "hand", "body": "forearm", "anchor": [0.254, 0.0, 0.0],
                          "target": [0.254, 0.0, 0.708]})
    control.serve(lab)
    forearm = arm.body_ids[arm.names.index("forearm")]
    pushed = lab.pushes[-1]
    # the spring: 400 N/m x 0.2 m straight up (the first push: no velocity yet to damp)
    assert np.allclose(pushed[forearm, :3], [0.0, 0.0, 80.0], atol=1e-6)
    assert np.all(np.delete(pushed, forearm, axis=0) == 0)
    control.command(lab, {"type": "release"})
    control.serve(lab)
    control.serve(lab)
    assert len(lab.pushes) == 2 and np.all(lab.pushes[-1] == 0)
