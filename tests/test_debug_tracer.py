"""The plumbing of ``crslab debug``: the debugger process started before the worker and held
until it is given the worker's process id (the id the worker names as its tracer must be the
debugger's), who traces whom, and the localhost-only port an IDE reaches gdbserver through."""

from __future__ import annotations

import os
import socket
import subprocess
import sys

import pytest

from crslab import os_support
from crslab.debug.local_port import LocalPort
from crslab.debug.tracer import GatedTracer, TracerError

REPORT_PID = "import os, sys; print(os.getpid(), sys.argv[1], flush=True)"


def test_the_gated_debugger_keeps_the_process_id_the_worker_named_and_gets_the_workers():
    tracer = GatedTracer([sys.executable, "-c", REPORT_PID], stdout=subprocess.PIPE)
    try:
        named = tracer.pid  # what the worker would hand to PR_SET_PTRACER before it exists
        tracer.release(4242)
        out, _ = tracer.process.communicate(timeout=60)
    finally:
        tracer.stop()
    assert out.decode().split() == [str(named), "4242"]  # exec kept the process: same id


def test_a_gate_closed_without_a_process_id_ends_without_running_the_debugger():
    tracer = GatedTracer([sys.executable, "-c", REPORT_PID], stdout=subprocess.PIPE)
    tracer.stop()
    assert tracer.process.stdout.read() == b"" and tracer.process.returncode != 0


def test_a_debugger_that_exits_instead_of_attaching_is_one_line(tmp_path):
    child = subprocess.Popen([sys.executable, "-c", "import sys; sys.stdin.read()"], stdin=subprocess.PIPE)
    tracer = GatedTracer([sys.executable, "-c", "import sys; sys.exit(1)"])
    try:
        tracer.release(child.pid)
        attach_failed = r"^python[\d.]* could not attach to the lab's process \(it exited with status 1"
        with pytest.raises(TracerError, match=attach_failed):
            tracer.wait_attached(child.pid, timeout_s=60)
    finally:
        tracer.stop()
        child.kill()
        child.wait()


def test_tracer_of_a_process_and_of_none():
    assert os_support.tracer_of(os.getpid()) == 0
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    assert os_support.tracer_of(child.pid) is None  # reaped: gone


SCOPES = [("0", None), ("1", None), ("2", "only root"), ("3", "no process")]


@pytest.mark.parametrize(("scope", "says"), SCOPES)
def test_ptrace_scopes_that_forbid_a_debugger_are_named(tmp_path, scope, says):
    f = tmp_path / "ptrace_scope"
    f.write_text(scope + "\n")
    found = os_support.ptrace_restriction(f)
    assert (found is None) if says is None else (says in found and f"is {scope}" in found)


def test_the_ide_port_listens_on_loopback_only_and_relays_both_ways():
    cat = subprocess.Popen(["cat"], stdin=subprocess.PIPE, stdout=subprocess.PIPE)  # an echoing "gdbserver"
    port = LocalPort(0)
    try:
        assert port.addresses and all(host in ("127.0.0.1", "::1") for host, _ in port.addresses)
        assert {p for _, p in port.addresses} == {port.port}
        port.relay(cat.stdin, cat.stdout)
        with socket.create_connection(("127.0.0.1", port.port), timeout=60) as conn:
            conn.sendall(b"$qSupported#37")
            got = b""
            while len(got) < 14:
                got += conn.recv(100)
            assert got == b"$qSupported#37"
        assert cat.wait(60) == 0  # the connection closed: its standard input too (gdbserver --once ends)
    finally:
        port.close()
        cat.kill()


def test_a_port_in_use_is_one_line():
    with LocalPort(0) as first:
        with pytest.raises(OSError, match=rf"^localhost port {first.port} cannot be listened on \("):
            LocalPort(first.port)
