"""Replicas of ``crslab serve`` behind the nginx configuration crslab ships (``nginx.conf`` beside
this file), all on this machine: what ``tests/test_serve_replicas.py`` and ``tools/bench.py serve
--replicas N`` start, and a TA may start to try the configuration before a course server has it.

nginx runs the shipped file with only what names a machine changed (:func:`local_configuration`):
the ports (free loopback ports instead of 80 and 443; the upstream lists the replicas' ports) and
where nginx keeps its pid, logs and temporary files (a folder of the caller's, with a throwaway
certificate in its ``tls/``). Every replica is ``crslab serve --users ROSTER --secret-file KEY``,
as docs/serve.md starts them.

>>> conf = local_configuration(SHIPPED.read_text(), 8080, 8443, [9001, 9002, 9003], Path("/srv/p"))
>>> [line.split("#")[0].strip() for line in conf.splitlines() if "listen" in line or "server 127" in line]
... # doctest: +NORMALIZE_WHITESPACE
['server 127.0.0.1:9001;', 'server 127.0.0.1:9002;', 'server 127.0.0.1:9003;',
 'listen 127.0.0.1:8080;', 'listen 127.0.0.1:8443 ssl http2;']
>>> "    proxy_temp_path /srv/p/proxy;" in conf.splitlines()
True
"""

from __future__ import annotations

import os
import re
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

SHIPPED = Path(__file__).with_name("nginx.conf")
"""The configuration crslab ships for N replicas behind nginx."""
_UPSTREAM = re.compile(r"^(\s*)server 127\.0\.0\.1:\d+;\n(?:\s*server 127\.0\.0\.1:\d+;\n)*", re.MULTILINE)
_TEMP_PATHS = ("client_body", "proxy", "fastcgi", "uwsgi", "scgi")
START_TIMEOUT_S = 60.0


class ReplicaError(RuntimeError):
    """A replica or nginx did not start (one line saying which, and what it printed)."""


def local_configuration(shipped: str, http_port: int, https_port: int, replicas: list[int],
                        folder: Path) -> str:
    """The shipped configuration ``shipped`` on this machine: nginx listens on loopback ports
    ``http_port`` and ``https_port`` (instead of 80 and 443), its upstream is ``replicas`` (ports on
    this machine), its temporary files and access log go into ``folder``; nothing else changes."""
    text = shipped.replace("listen 80;", f"listen 127.0.0.1:{http_port};")
    text = text.replace("listen 443 ssl", f"listen 127.0.0.1:{https_port} ssl")
    servers = lambda m: "".join(f"{m.group(1)}server 127.0.0.1:{p};\n" for p in replicas)  # noqa: E731
    text, found = _UPSTREAM.subn(servers, text, count=1)
    if found != 1 or f"listen 127.0.0.1:{https_port} ssl" not in text:
        raise ReplicaError("the shipped nginx.conf no longer has the listen and upstream lines this expects")
    paths = "".join(f"    {kind}_temp_path {folder / kind};\n" for kind in _TEMP_PATHS)
    return text.replace("http {\n", f"http {{\n{paths}    access_log {folder / 'access.log'};\n", 1)


def free_port() -> int:
    """A TCP port no one listens on now (loopback)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _listening(port: int) -> bool:
    try:
        socket.create_connection(("127.0.0.1", port), timeout=1.0).close()
    except OSError:
        return False
    return True


class Replica:
    """One ``crslab serve`` (its process group of its own), listening on :attr:`port`."""

    def __init__(self, folder: Path, roster: Path, key: Path, options: list[str], nice: list[str]) -> None:
        self.log = folder / "serve.log"
        with open(self.log, "w") as log:
            self.proc = subprocess.Popen(
                [*nice, sys.executable, "-m", "crslab", "serve", "--port", "0", "--users", str(roster),
                 "--secret-file", str(key), *options],
                stderr=log, stdout=subprocess.DEVNULL, cwd=folder, start_new_session=True)
        deadline = time.monotonic() + START_TIMEOUT_S
        url = None
        while url is None:
            url = re.search(r"http://127\.0\.0\.1:(\d+)", self.log.read_text())
            if url is None and (self.proc.poll() is not None or time.monotonic() > deadline):
                self.stop()
                raise ReplicaError(f"crslab serve did not start: {self.log.read_text()[-2000:]}")
            if url is None:
                time.sleep(0.05)
        self.port = int(url.group(1))

    def stop(self) -> None:
        """Ctrl-C, as a user stops it (killed if it has not ended within 30 s)."""
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGINT)
            try:
                self.proc.wait(30)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()


class Replicas:
    """``count`` replicas sharing ``roster`` and a cookie key, behind nginx with the shipped
    configuration (``options``: more of ``crslab serve``'s; ``nice``: a command prefix for the
    replicas, e.g. ``["nice", "-n", "-10"]``). :attr:`https` is where nginx serves them; use it as
    a context manager, or :meth:`stop`."""

    def __init__(self, folder: Path, roster: Path, count: int = 2, options: list[str] | None = None,
                 nice: list[str] | None = None) -> None:
        self.folder = folder
        self.replicas: list[Replica] = []
        self.nginx: subprocess.Popen | None = None
        key = folder / "cookie.key"
        key.write_text(os.urandom(32).hex() + "\n")
        key.chmod(0o600)
        try:
            for i in range(count):
                (folder / f"replica{i}").mkdir()
                self.replicas.append(Replica(folder / f"replica{i}", roster, key, options or [], nice or []))
            self._start_nginx()
        except BaseException:
            self.stop()
            raise

    @property
    def ports(self) -> list[int]:
        """The replicas' own ports (reached directly, not through nginx)."""
        return [r.port for r in self.replicas]

    @property
    def https(self) -> str:
        """``127.0.0.1:PORT``: nginx's TLS side, where the pages go."""
        return f"127.0.0.1:{self.https_port}"

    def _start_nginx(self) -> None:
        conf_dir = self.folder / "nginx"
        (conf_dir / "tls").mkdir(parents=True)
        made = subprocess.run(
            ["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1", "-subj",
             "/CN=127.0.0.1", "-keyout", str(conf_dir / "tls" / "privkey.pem"),
             "-out", str(conf_dir / "tls" / "fullchain.pem")],
            capture_output=True, text=True)
        if made.returncode != 0:
            raise ReplicaError(f"openssl could not make a certificate: {made.stderr.strip()[-500:]}")
        self.http_port, self.https_port = free_port(), free_port()
        conf = conf_dir / "nginx.conf"
        conf.write_text(local_configuration(SHIPPED.read_text(), self.http_port, self.https_port,
                                            self.ports, conf_dir))
        main = f"daemon off; pid {conf_dir / 'nginx.pid'}; error_log {conf_dir / 'error.log'};"
        if os.geteuid() == 0:
            main += " user root;"  # its workers write the temporary files into this (private) folder
        self.nginx = subprocess.Popen(["nginx", "-p", str(conf_dir), "-c", str(conf), "-g", main],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                                      start_new_session=True)
        deadline = time.monotonic() + START_TIMEOUT_S
        while not _listening(self.https_port):
            if self.nginx.poll() is not None or time.monotonic() > deadline:
                said = self.nginx.stderr.read() if self.nginx.stderr else ""
                logged = (conf_dir / "error.log").read_text()[-1500:]
                raise ReplicaError(f"nginx did not start: {said} {logged}")
            time.sleep(0.05)

    def stop(self) -> None:
        """nginx, then every replica."""
        if self.nginx is not None and self.nginx.poll() is None:
            self.nginx.terminate()
            try:
                self.nginx.wait(10)
            except subprocess.TimeoutExpired:
                self.nginx.kill()
                self.nginx.wait()
        for replica in self.replicas:
            replica.stop()

    def __enter__(self) -> Replicas:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()
