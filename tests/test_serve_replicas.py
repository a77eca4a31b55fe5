"""Two replicas of ``crslab serve`` behind nginx with the configuration crslab ships
(crslab/serve/deploy/nginx.conf, only its ports and nginx's own files moved: replicas.py), on this
machine: logins through nginx, pages opened and labs run through it (TLS and WebSockets), a user's
pages on one replica, a login made on either replica good on both, and both replicas serving."""

from __future__ import annotations

import html
import http.client
import json
import re
import socket
import ssl

import pytest
from serve_server import USERS, run_message, write_roster
from websockets.typing import Origin

from crslab.serve.auth import hash_password
from crslab.serve.deploy.replicas import Replicas
from crslab.sinks.page_stream import unpacked_rows
from crslab.starters import starter_text

STUDENTS = [f"student{i:02d}" for i in range(16)]
"""Enough that both replicas get some (nginx hashes the user's name: each lands on one of two)."""
TLS = ssl.create_default_context()
TLS.check_hostname = False
TLS.verify_mode = ssl.CERT_NONE  # nginx's throwaway certificate


@pytest.fixture(scope="module")
def replicas(tmp_path_factory):
    folder = tmp_path_factory.mktemp("replicas")
    roster = write_roster(folder)
    with open(roster, "a") as f:
        for name in STUDENTS:
            f.write(f"{name},{hash_password(name + '-password', iterations=1000)},student\n")
    with Replicas(folder, roster, count=2, options=["--compiles-per-minute", "1000"]) as running:
        yield running


def request(host: str, method: str, path: str, body: dict | None = None, cookie: str = "",
            tls: bool = True) -> tuple[int, dict[str, str], bytes]:
    conn = (http.client.HTTPSConnection(host, timeout=60, context=TLS) if tls
            else http.client.HTTPConnection(host, timeout=60))
    headers = {"Cookie": cookie} if cookie else {}
    data = None
    if body is not None:
        data, headers["Content-Type"] = json.dumps(body).encode(), "application/json"
    conn.request(method, path, body=data, headers=headers)
    r = conn.getresponse()
    payload = r.read()
    cookies = {k: v for key, value in r.getheaders() if key.lower() == "set-cookie"
               for k, _, v in [value.split(";")[0].partition("=")]}
    conn.close()
    return r.status, cookies, payload


def password(name: str) -> str:
    return USERS[name][0] if name in USERS else name + "-password"


def login(host: str, name: str, tls: bool = True) -> str:
    """The Cookie header of ``name`` logged in at ``host`` (nginx, or a replica directly)."""
    status, cookies, body = request(host, "POST", "/api/login", {"name": name, "password": password(name)},
                                    tls=tls)
    assert status == 200, body
    return "; ".join(f"{k}={v}" for k, v in cookies.items())


class Page:
    """A page's WebSocket through nginx (wss), read and written from this one thread: websockets'
    sans-I/O protocol on a blocking TLS socket. (websockets' synchronous client reads its socket in a
    thread while it writes from another; under TLS 1.3 the session tickets nginx sends just after
    the handshake woke that reader while the opening request was written, an SSL socket is not safe
    for both at once, and about one run of this test in 27 lost a page's request: nginx logged
    "client timed out while waiting for request". With one thread, 0 in 200 pages.)"""

    def __init__(self, replicas: Replicas, cookie: str) -> None:
        from websockets.client import ClientProtocol
        from websockets.uri import parse_uri

        host, port = replicas.https.rsplit(":", 1)
        raw = socket.create_connection((host, int(port)), timeout=60)
        self.sock = TLS.wrap_socket(raw, server_hostname=host)
        self.sock.settimeout(120)
        self.protocol = ClientProtocol(parse_uri(f"wss://{replicas.https}/ws"),
                                       origin=Origin(f"https://{replicas.https}"), max_size=None)
        self.request = self.protocol.connect()
        self.request.headers["Cookie"] = cookie
        self.protocol.send_request(self.request)
        self._flush()
        self.messages: list[str] = []
        self._parts: list[bytes] = []  # a text message's frames so far
        self.hello = self.next()
        assert self.hello["type"] == "hello", self.hello

    def _flush(self) -> None:
        for data in self.protocol.data_to_send():
            if data:
                self.sock.sendall(data)

    def _text(self) -> str:
        """The next text message (the opening handshake's response and control frames in between
        are the protocol's)."""
        from websockets.frames import Opcode
        from websockets.http11 import Response

        while not self.messages:
            data = self.sock.recv(65536)
            if data:
                self.protocol.receive_data(data)
            else:
                self.protocol.receive_eof()
            self._flush()
            for event in self.protocol.events_received():
                if isinstance(event, Response):
                    assert event.status_code == 101, (event.status_code, event.body)
                elif event.opcode in (Opcode.TEXT, Opcode.CONT):
                    self._parts.append(event.data)
                    if event.fin:
                        self.messages.append(b"".join(self._parts).decode())
                        self._parts.clear()
            if not data:
                assert self.messages, f"the server closed the page's WebSocket ({self.protocol.close_exc})"
        return self.messages.pop(0)

    def next(self) -> dict:
        msg = json.loads(self._text())
        if msg.get("type") == "chunk":
            msg["frames"] = unpacked_rows(msg["frames"])
        return msg

    def send(self, text: str) -> None:
        self.protocol.send_text(text.encode())
        self._flush()

    def run(self, seconds: float) -> list[dict]:
        self.send(json.dumps(run_message(starter_text("lab1", "A"), "lab1.c", duration=seconds,
                                                  no_startup_delay=True)))
        got = [self.next()]
        while got[-1]["type"] != "ended":
            assert got[-1]["type"] != "error", got[-1]
            got.append(self.next())
        return got

    def close(self) -> None:
        self.protocol.send_close()
        self._flush()
        self.sock.close()


def sessions_on(replicas: Replicas, admin: str) -> list[list[str]]:
    """Per replica (asked directly, not through nginx), the users of its open pages (its /admin)."""
    out = []
    for port in replicas.ports:
        status, _, body = request(f"127.0.0.1:{port}", "GET", "/admin", cookie=admin, tls=False)
        assert status == 200, body
        rows = re.findall(r"<tr>((?:<td>.*?</td>)+)</tr>", body.decode())
        out.append([html.unescape(re.findall(r"<td>(.*?)</td>", row)[1]) for row in rows])
    return out


@pytest.mark.requires("nginx", "openssl")
def test_two_replicas_behind_the_shipped_nginx(replicas):
    admin = login(replicas.https, "ta")  # logged in through nginx: its cookie is good on both replicas
    status, _, me = request(replicas.https, "GET", "/api/me", cookie=admin)
    assert status == 200 and json.loads(me)["admin"] is True

    # pages of one user after another, until both replicas hold some
    pages, where = {}, {}
    for name in STUDENTS:
        pages[name] = Page(replicas, login(replicas.https, name))
        on = sessions_on(replicas, admin)
        where[name] = [i for i, users in enumerate(on) if name in users]
        assert len(where[name]) == 1, (name, on)  # its page is on one replica
        if len(set(w[0] for w in where.values())) == 2:
            break
    on_a = next(n for n in where if where[n] == [0])
    on_b = next(n for n in where if where[n] == [1])

    # both replicas run labs, each the same bytes as the other (the same lab, the same scenario)
    runs = {name: pages[name].run(1.0) for name in (on_a, on_b)}
    for got in runs.values():
        assert got[-1]["status"] == "ok" and got[-1]["end_tick"] == 1000
    serial = {name: "".join(t for m in got if m["type"] == "chunk" for _, t in m["serial"])
              for name, got in runs.items()}
    assert serial[on_a] == serial[on_b] and serial[on_a]

    # a user's second page, and their download, go to the replica that holds their first
    second = Page(replicas, login(replicas.https, on_a))
    assert sessions_on(replicas, admin)[0].count(on_a) == 2 and on_a not in sessions_on(replicas, admin)[1]
    cookie = login(replicas.https, on_a)
    download = f"/api/download/transcript?session={pages[on_a].hello['session']}"
    status, _, body = request(replicas.https, "GET", download, cookie=cookie)
    assert status == 200 and body.decode("latin-1") == serial[on_a]
    second.close()

    # a login made directly at either replica is good through nginx, wherever the user's pages are
    for port in replicas.ports:
        for name in (on_a, on_b):
            direct = login(f"127.0.0.1:{port}", name, tls=False)
            status, _, me = request(replicas.https, "GET", "/api/me", cookie=direct)
            assert status == 200 and json.loads(me)["user"] == name
            page = Page(replicas, direct)
            assert page.hello["user"] == name
            page.close()
    for page in pages.values():
        page.close()
