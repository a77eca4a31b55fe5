"""A real ``crslab serve`` for the tests: started as a user starts it, waited on by the line it
prints, with a roster of test users, and a small WebSocket client speaking its protocol."""

from __future__ import annotations

import http.client
import json
import os
import re
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

from waiting import LineWatcher, wait_exit

from crslab.serve.auth import hash_password
from crslab.sinks.page_stream import unpacked_rows

USERS = {
    "alice": ("alice-password", "student"),
    "bob": ("bob-password", "student"),
    "ta": ("ta-password-1", "admin"),
}
"""name: (password, role): the roster the tests' server serves."""


def write_roster(folder: Path) -> Path:
    """A roster of :data:`USERS` (hashes with few iterations: the tests log in often)."""
    lines = ["name,secret,role"]
    lines += [f"{n},{hash_password(p, iterations=1000)},{r}" for n, (p, r) in USERS.items()]
    path = folder / "roster.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


class ServeProcess:
    """``crslab serve --port 0 ...`` in a process of its own; :attr:`url` once it listens."""

    def __init__(self, folder: Path, *args: str) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "crslab", "serve", "--port", "0", *args],
            stderr=subprocess.PIPE,
            stdout=subprocess.DEVNULL,
            text=True,
            cwd=folder,
            start_new_session=True,
        )
        self.stderr = LineWatcher(self.proc.stderr, "crslab serve's stderr")
        line = self.stderr.wait_for(r"http://")[-1]
        self.url = re.search(r"http://\S+", line).group(0)
        self.host = self.url.split("/")[2]

    def request(
        self, method: str, path: str, body: dict | None = None, cookie: str = ""
    ) -> tuple[int, dict[str, str], bytes]:
        conn = http.client.HTTPConnection(self.host, timeout=60)
        headers = {"Cookie": cookie} if cookie else {}
        data = None
        if body is not None:
            data = json.dumps(body).encode()
            headers["Content-Type"] = "application/json"
        conn.request(method, path, body=data, headers=headers)
        r = conn.getresponse()
        payload = r.read()
        cookies = {}
        for key, value in r.getheaders():
            if key.lower() == "set-cookie":
                name, _, rest = value.partition("=")
                cookies[name] = rest.split(";")[0]
        conn.close()
        return r.status, cookies, payload

    def login(self, name: str) -> str:
        """The Cookie header of ``name`` logged in with the roster's password."""
        status, cookies, body = self.request("POST", "/api/login", {"name": name, "password": USERS[name][0]})
        assert status == 200, body
        return "; ".join(f"{k}={v}" for k, v in cookies.items())

    def stop(self) -> None:
        os.killpg(self.proc.pid, signal.SIGINT)
        wait_exit(self.proc, "Ctrl-C")
        self.stderr.all()


class Client:
    """A page's WebSocket, synchronous: :meth:`send` a message, :meth:`next` the server's next one."""

    def __init__(self, server: ServeProcess, cookie: str, origin: str | None = None) -> None:
        from websockets.sync.client import connect

        headers = {"Cookie": cookie, "Origin": origin if origin is not None else f"http://{server.host}"}
        self.ws = connect(
            f"ws://{server.host}/ws", additional_headers=headers, open_timeout=60, max_size=None
        ).__enter__()
        self.hello = self.next()
        assert self.hello["type"] == "hello", self.hello

    def send(self, msg: dict | str) -> None:
        self.ws.send(msg if isinstance(msg, str) else json.dumps(msg))

    def next(self, timeout_s: float = 120.0) -> dict:
        """The server's next message; a chunk's frames unpacked into rows, as the page unpacks them."""
        msg = json.loads(self.ws.recv(timeout=timeout_s))
        if msg.get("type") == "chunk" and "frames" in msg:
            msg["frames"] = unpacked_rows(msg["frames"])
        return msg

    def until(self, kind: str) -> list[dict]:
        """Every message up to and including the first of type ``kind`` (an ``error`` first fails)."""
        got = []
        while True:
            msg = self.next()
            got.append(msg)
            if msg["type"] == kind:
                return got
            assert msg["type"] != "error", f"waiting for {kind}, the server refused: {msg['message']}"

    def close(self) -> None:
        self.ws.close()


def serial_of(messages: list[dict]) -> list[tuple[int, bytes]]:
    """The serial bytes the chunks carried, with their ticks."""
    return [
        (tick, text.encode("latin-1")) for m in messages if m["type"] == "chunk" for tick, text in m["serial"]
    ]


def run_message(lab: Path | str, name: str = "lab.c", **options: object) -> dict:
    """A ``run`` message for a lab file (or text), as the page sends it."""
    text = lab.read_text() if isinstance(lab, Path) else lab
    msg = {"type": "run", "lab": {"name": name, "text": text}, "scenario": {"name": "tour"}, "speed": None}
    msg.update(options)
    return msg


def roster_server(tmp_path_factory, *options: str) -> Iterator[ServeProcess]:  # noqa: ANN001 - pytest's
    """A module's server with the test roster and room for the module's compiles (``options``:
    more of ``crslab serve``'s), stopped when the module is done: ``yield from roster_server(...)``
    in a module-scoped fixture."""
    folder = tmp_path_factory.mktemp("serve")
    server = ServeProcess(folder, "--users", str(write_roster(folder)), "--compiles-per-minute", "1000",
                          *options)
    try:
        yield server
    finally:
        server.stop()


def logged_in(server: ServeProcess, user: str) -> Iterator[Client]:
    """A page of ``user``'s on ``server``, closed when done: ``yield from logged_in(...)``."""
    client = Client(server, server.login(user))
    try:
        yield client
    finally:
        client.close()
