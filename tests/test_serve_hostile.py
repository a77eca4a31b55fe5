"""crslab serve against a hostile page user (issue 31's findings 4 to 8): each test makes the
attack and checks the server's answer.

- 5: a golden file's ``scenario:`` line names only a built-in scenario or the one uploaded into the
  page; a server path gets the same one line whether the file is there or not, quoting none of it;
- 6: one user holds at most ``--max-sessions-per-user`` pages, whatever ``--max-sessions`` allows;
- 7: wrong passwords and tokens back off per name and address pair and per client address, and the
  right password gets in once the (short) back-off is over (issue 38: from an address that has not
  been guessing, at once);
- 8: no message names a server path (the cache, the install, the session's folder);
- 4: a user's builds run one at a time, and a build ends with the page that started it.

The login limits run in this process on the application (its clock is the test's: no sleeps); the
rest on a real ``crslab serve``.
"""

from __future__ import annotations

import asyncio
import json
import re
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

import pytest
from json_strings import json_strings
from serve_server import USERS, Client, ServeProcess, logged_in, roster_server, run_message, write_roster
from serve_tables import start_without_processes, table_session
from waiting import wait_gone, wait_until

import crslab
from crslab.cache import cache_dir
from crslab.serve.app import ServeSettings, make_app
from crslab.serve.auth import ADDRESS_BACKOFF, PAIR_BACKOFF, Backoff, CookieSigner, load_roster
from crslab.serve.page_process import SessionLimits
from crslab.serve.page_sessions import LimitError, PageSession, Sessions, UserLimits
from crslab.starters import starter_text

LAB_A = starter_text("lab1", "A")
REPO = Path(__file__).resolve().parents[1]


# -- the login limits, in this process ------------------------------------------------------------
class Clock:
    """The application's clock, moved by the test."""

    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


def call(app, method: str, path: str, body: dict | None = None,
         address: str = "10.0.0.1") -> tuple[int, dict]:
    """One HTTP request to the ASGI application from ``address``: its status and headers, with the
    JSON body's ``error`` (or the page's text) as ``headers['body']``."""
    path, _, query = path.partition("?")
    data = json.dumps(body).encode() if body is not None else b""
    scope = {
        "type": "http", "asgi": {"version": "3.0"}, "http_version": "1.1", "method": method,
        "scheme": "http", "path": path, "raw_path": path.encode(), "query_string": query.encode(),
        "root_path": "", "headers": [(b"host", b"crslab.test"), (b"content-type", b"application/json")],
        "client": (address, 40000), "server": ("crslab.test", 80),
    }
    sent: list[dict] = []
    chunks = [{"type": "http.request", "body": data, "more_body": False}]

    async def receive() -> dict:
        return chunks.pop(0) if chunks else {"type": "http.disconnect"}

    async def send(message: dict) -> None:
        sent.append(message)

    asyncio.run(app(scope, receive, send))
    start = next(m for m in sent if m["type"] == "http.response.start")
    headers = {k.decode().lower(): v.decode() for k, v in start["headers"]}
    text = b"".join(m.get("body", b"") for m in sent if m["type"] == "http.response.body").decode()
    try:
        headers["body"] = json.loads(text).get("error", text)
    except ValueError:
        headers["body"] = text
    return start["status"], headers


@pytest.fixture
def roster_app(tmp_path):
    clock = Clock()
    roster = load_roster(write_roster(tmp_path))
    sessions = Sessions(UserLimits(), SessionLimits())
    return make_app(ServeSettings(roster, CookieSigner(b"k" * 32)), sessions, clock), clock


def login(app, name: str, password: str, address: str = "10.0.0.1") -> tuple[int, str]:
    status, headers = call(app, "POST", "/api/login", {"name": name, "password": password}, address)
    return status, headers["body"]


def test_the_back_off_doubles_from_the_first_try_past_the_free_ones_and_stops_at_its_cap():
    b = Backoff(free=5, base_s=1.0, max_s=30.0)
    waits = []
    now = 0.0
    for _ in range(12):
        b.tried("x", now)
        waits.append(b.wait_s("x", now))
        now += waits[-1]  # each try as soon as the back-off lets it in
    assert waits == [0, 0, 0, 0, 0, 1, 2, 4, 8, 16, 30, 30]
    assert b.wait_s("x", now - 0.25) == 0.25 and b.wait_s("other", now) == 0
    b.tried("x", now)  # a quiet quarter of an hour later, x starts afresh
    assert b.wait_s("x", now + 900.0) == 0
    b.tried("x", now + 900.0)
    assert b.wait_s("x", now + 900.0) == 0


def test_guesses_from_elsewhere_never_hold_back_the_right_password(roster_app):
    """Issue 38: 14 wrong tries at alice's name from another address kept her right password
    refused for 114 s. The back-off is per name and address pair: alice, from an address that has
    not been guessing, is let in at once; the guessing address backs off (its cap 30 s)."""
    app, clock = roster_app
    free = PAIR_BACKOFF["free"]
    for _ in range(14):
        clock.now += 0.1
        login(app, "alice", "guess", address="10.6.6.6")
    assert login(app, "alice", USERS["alice"][0], address="10.9.9.9") == (200, '{"user":"alice"}')
    # the guessing address: the pair shuts it out, the right password too (it may be the attacker)
    status, text = login(app, "alice", USERS["alice"][0], address="10.6.6.6")
    assert status == 429 and text.startswith("too many wrong passwords for this name from your address")
    # the back-off at its edge: the free tries pass, the next waits 1 s, then 2 s, ... at most 30 s
    clock.now += 1000.0  # forgotten
    for _ in range(free):
        assert login(app, "alice", "guess", address="10.7.7.7") == (401, "wrong name or password")
    assert login(app, "alice", "guess", address="10.7.7.7") == (401, "wrong name or password")
    status, headers = call(app, "POST", "/api/login", {"name": "alice", "password": "x"}, "10.7.7.7")
    assert status == 429 and headers["retry-after"] == "1"
    for i in range(12):
        clock.now += Backoff(**PAIR_BACKOFF).delay_s(free + 1 + i)
        assert login(app, "alice", "guess", address="10.7.7.7")[0] == 401
    status, text = login(app, "alice", USERS["alice"][0], address="10.7.7.7")
    assert status == 429 and text.endswith("try again in 30 s")
    clock.now += 29.5
    assert login(app, "alice", USERS["alice"][0], address="10.7.7.7")[0] == 429
    clock.now += 0.5  # the cap: 30 s after its last try, the address may log in
    assert login(app, "alice", USERS["alice"][0], address="10.7.7.7") == (200, '{"user":"alice"}')
    assert login(app, "alice", "typo", address="10.7.7.7") == (401, "wrong name or password")  # afresh
    # and other names from that address were never held back by alice's pair
    assert login(app, "bob", USERS["bob"][0], address="10.6.6.6") == (200, '{"user":"bob"}')


def test_wrong_passwords_from_one_address_back_off_whatever_the_names(roster_app):
    """Finding 7: no limit across names let one address try a password on every name (each try a
    PBKDF2 on the server)."""
    app, clock = roster_app
    free = ADDRESS_BACKOFF["free"]
    for i in range(free + 1):
        assert login(app, f"student{i}", "password1", address="10.3.3.3")[0] == 401
    status, text = login(app, "someone-new", "password1", address="10.3.3.3")
    assert status == 429 and text == "too many wrong passwords from your address; try again in 1 s"
    # another address is not held back, and the name tried from it is not locked
    assert login(app, "bob", USERS["bob"][0], address="10.4.4.4")[0] == 200
    clock.now += 1.0
    assert login(app, "student99", "password1", address="10.3.3.3")[0] == 401
    status, text = login(app, "bob", USERS["bob"][0], address="10.3.3.3")
    assert status == 429 and text.endswith("try again in 2 s")


def test_token_guesses_back_off_per_address():
    """Finding 7: ``/?token=`` took 300 guesses in 1.2 s; now it backs off as the passwords do, and
    the right token gets in once the back-off is over."""
    clock = Clock()
    token = "the-printed-token-Qm3x"
    app = make_app(ServeSettings(None, CookieSigner(b"k" * 32), local_token=token),
                   Sessions(UserLimits(), SessionLimits()), clock)
    statuses = [call(app, "GET", f"/?token=guess{i}", address="10.5.5.5")[0] for i in range(300)]
    free = ADDRESS_BACKOFF["free"]
    assert statuses[: free + 1] == [200] * (free + 1)  # the page (with its login), no cookie
    assert set(statuses[free + 1 :]) == {429}
    status, headers = call(app, "GET", f"/?token={token}", address="10.5.5.5")
    assert status == 429 and "too many wrong tokens or passwords from your address; try again in 1 s" \
        in headers["body"]
    assert call(app, "GET", f"/?token={token}", address="10.6.6.6")[0] == 303  # another address
    clock.now += 1.0
    status, headers = call(app, "GET", f"/?token={token}", address="10.5.5.5")
    assert status == 303 and headers["location"] == "/" and "crslab_user=you" in headers["set-cookie"]


# -- sessions per user: the table alone ----------------------------------------------------------
def test_one_user_opening_pages_at_once_holds_at_most_the_per_user_cap(monkeypatch, tmp_path):
    """Finding 6: with ``--max-sessions 6``, one student's 8 pages, opened at once (the server
    starts each in a thread), hold 2; the next student still gets in."""
    sessions = Sessions(UserLimits(max_sessions=6, max_sessions_per_user=2), SessionLimits())
    release = threading.Event()

    def fake_start(user: str) -> PageSession:
        if user == "mallory":
            release.wait()  # her admitted pages are still starting while the others ask
        return table_session(f"{user}-{threading.get_ident()}", user, Path(tmp_path))

    start_without_processes(monkeypatch, sessions, fake_start)
    outcomes: list[str] = []

    def open_page() -> None:
        try:
            sessions.start("mallory")
            outcomes.append("open")
        except LimitError as exc:
            outcomes.append(str(exc))

    threads = [threading.Thread(target=open_page, daemon=True) for _ in range(8)]
    for t in threads:
        t.start()
    try:
        wait_until(lambda: len(outcomes) >= 6, "six of mallory's eight pages refused while two start")
    finally:
        release.set()
    for t in threads:
        t.join()
    assert outcomes.count("open") == 2
    refused = [o for o in outcomes if o != "open"]
    assert refused == ["you have 2 pages open on this server, as many as one user may (2): close one to "
                       "open this one"] * 6
    assert sessions.start("bob").user == "bob"
    mine = [s for s in sessions.all() if s.user == "mallory"]
    sessions.close(mine[0])
    assert sessions.start("mallory").user == "mallory"  # a page closed: another may open


# -- a real server -------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def server(tmp_path_factory):
    yield from roster_server(tmp_path_factory, "--max-sessions", "6")


@pytest.fixture(scope="module")
def alice(server):
    yield from logged_in(server, "alice")


def test_one_user_cannot_take_every_session(server, alice):
    """Finding 6 on the server: alice's second page opens, her third is told why it does not;
    bob (with 4 of the 6 places free) still gets his."""
    from websockets.exceptions import ConnectionClosed

    second = Client(server, server.login("alice"))
    try:
        from websockets.sync.client import connect

        headers = {"Cookie": server.login("alice"), "Origin": f"http://{server.host}"}
        with connect(f"ws://{server.host}/ws", additional_headers=headers, open_timeout=60) as third:
            refused = json.loads(third.recv(timeout=60))
            assert refused == {"type": "error", "message": "you have 2 pages open on this server, as many "
                               "as one user may (2): close one to open this one"}
            with pytest.raises(ConnectionClosed) as closed:
                third.recv(timeout=60)
            assert closed.value.rcvd.code == 4429
        bob = Client(server, server.login("bob"))
        bob.close()
    finally:
        second.close()


def _golden(scenario: str) -> str:
    return (f"# crslab transcript: the exact bytes the lab printed follow the '# ----' line\n"
            f"# scenario: {scenario}\n# end_s: 1.000\n# ----\n")


def test_a_golden_file_cannot_name_a_server_file_as_its_scenario(alice, tmp_path):
    """Finding 5: a readable TOML file of the server (its keys would be quoted), a file that is
    not there, a climb out of the session: one line, the same for each, quoting nothing."""
    absent = tmp_path / "absent" / "nothing.toml"
    replies = []
    for named in (str(REPO / "pyproject.toml"), str(absent), "../lab/lab1.c", "/etc/passwd"):
        alice.send({"type": "check", "lab": {"name": "lab1.c", "text": LAB_A},
                    "golden": {"name": "golden.txt", "text": _golden(named)}})
        replies.append(alice.until("checked")[-1])
    assert replies[0] == {"type": "checked", "ok": False, "report": (
        "golden.txt: its scenario is neither a built-in scenario nor the scenario file uploaded into "
        "this page (Run with it first); the page runs no other")}
    assert all(r == replies[0] for r in replies)


def test_a_golden_file_names_a_built_in_scenario_or_the_uploaded_one(server, alice, tmp_path):
    scenario = 'name = "still"\ndescription = "the arm left alone"\nend = 1.0\n'
    lab = tmp_path / "lab1.c"
    lab.write_text(LAB_A)
    (tmp_path / "still.toml").write_text(scenario)
    golden = tmp_path / "golden.txt"
    subprocess.run([sys.executable, "-m", "crslab", "record", "--lab", str(lab), "--scenario",
                    str(tmp_path / "still.toml"), "-o", str(golden)], check=True, capture_output=True)
    header = golden.read_text(encoding="latin-1")
    assert f"# scenario: {tmp_path / 'still.toml'}\n" in header
    text = header.replace(str(tmp_path / "still.toml"), "still.toml")  # as a student's folder holds it
    check = {"type": "check", "lab": {"name": "lab1.c", "text": LAB_A},
             "golden": {"name": "golden.txt", "text": text}}
    alice.send(check)
    assert "neither a built-in scenario" in alice.until("checked")[-1]["report"]  # not uploaded yet
    alice.send(run_message(LAB_A, duration=0.1, scenario={"file": {"name": "still.toml", "text": scenario}}))
    assert alice.until("ended")[-1]["status"] == "ok"
    alice.send(check)
    checked = alice.until("checked")[-1]
    assert checked["ok"] and checked["report"].startswith("match: ")
    alice.send({**check, "golden": {"name": "golden.txt", "text": _golden("hands_off")}})
    assert not alice.until("checked")[-1]["report"].startswith("golden.txt: its scenario")


SERVER_PATHS = [p for p in {str(Path.home()), tempfile.gettempdir(), sys.prefix, str(REPO),
                            str(Path(crslab.__file__).parent)} if len(p) > 1]


def test_messages_name_the_users_files_never_a_server_path(server, alice):
    """Finding 8: a compile error inside a system header and one inside crslab's, a malformed
    uploaded scenario: the page reads the names it gave (and the headers' own names), no folder."""
    got = []
    stdio_error = "#define FILE 3\n#include <stdio.h>\nvoid lab(void) {}\n"  # an error inside stdio.h
    alice.send({"type": "build", "lab": {"name": "my lab.c", "text": stdio_error}})
    got += alice.until("built")
    crslab_error = "#define Uint16 3.0\n" + LAB_A  # an error inside crslab's F28335 headers
    alice.send({"type": "build", "lab": {"name": "lab1.c", "text": crslab_error}})
    got += alice.until("built")
    alice.send(run_message(LAB_A, scenario={"file": {"name": "bad.toml", "text": "end = \"soon\"\n"}}))
    got += alice.until("ended")
    texts = [s for m in got for s in json_strings(m)]
    leaks = [(p, t) for t in texts for p in [*SERVER_PATHS, str(cache_dir()), "crslab-serve-"] if p in t]
    assert not leaks
    # nor any other absolute path: a header's name is its own (stdio.h), never a folder's
    assert [t for t in texts if re.search(r"(?:^|[\s'\"(])~?/[^\s/]", t)] == []
    first, second, ended = got[0], [m for m in got if m["type"] == "built"][1], got[-1]
    output = first["compiler_output"]
    assert not first["ok"] and "my lab.c:2:" in output and "stdio.h:" in output
    assert not second["ok"] and "tistdtypes.h:9:18: error" in second["compiler_output"]
    assert ended["bad_input"] and ended["message"].startswith("bad.toml")


SLOW_LAB = ("#if __INCLUDE_LEVEL__ < 26  /* 2**26 includes: past the compiler's limits */\n"
            '#include "slow_compile.c"\n#include "slow_compile.c"\n#endif\nvoid lab(void) {}\n')
"""A lab whose compile runs until the compiler's CPU limit: it includes itself twice, 26 deep."""


def _compilers(server: ServeProcess) -> list[int]:
    """The compiler processes the server started (its descendants) on a page's lab (its build's
    ``submission`` folder), not those of crslab's own C."""
    parents = {}
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit():
                stat = (entry / "stat").read_text()
                parents[int(entry.name)] = int(stat[stat.rindex(")") + 2 :].split()[1])
        except OSError:
            pass

    def descends(pid: int) -> bool:
        seen = 0
        while pid > 1 and seen < 64:
            pid, seen = parents.get(pid, 0), seen + 1
            if pid == server.proc.pid:
                return True
        return False

    found = []
    for pid in parents:
        try:
            cmdline = Path(f"/proc/{pid}/cmdline").read_bytes()
        except OSError:
            continue
        if b"zig" in cmdline and b"/submission" in cmdline and descends(pid):
            found.append(pid)
    return found


def test_a_users_builds_run_one_at_a_time_and_end_with_the_page(server):
    """Finding 4 on the server: while one page builds, the user's other page may not start a build;
    when the building page closes, its compiler ends with it (no zig or clang left running)."""
    first = Client(server, server.login("bob"))
    second = Client(server, server.login("bob"))
    try:
        # a lab built first: in a fresh cache zig builds its C library then (minutes on a busy machine)
        first.send({"type": "build", "lab": {"name": "lab1.c", "text": LAB_A}})
        while first.next(timeout_s=900.0)["type"] != "built":
            pass
        first.send({"type": "build", "lab": {"name": "slow_compile.c", "text": SLOW_LAB}})
        pids = wait_until(lambda: _compilers(server), "a compiler working on bob's lab")
        second.send({"type": "build", "lab": {"name": "lab1.c", "text": LAB_A}})
        assert second.next() == {"type": "error", "message": "build: you have a build going on in another "
                                 "page; one build, run or check at a time"}
    finally:
        first.close()
    wait_gone(pids, "the page that started the build closed", timeout_s=30.0)
    second.send({"type": "build", "lab": {"name": "lab1.c", "text": LAB_A}})  # the user may build again
    assert second.until("built")[-1]["ok"]
    second.close()
