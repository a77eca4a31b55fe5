"""A page's golden-file check (crslab/serve/page_process.py, ``Session.check``) runs its lab in the
session's own worker as fast as it can, within the server's limits (``--check-cpu-s``,
``--check-wall-s``): a lab slower than real time (some 9 million instructions a call, against a
golden file of 10 simulated seconds: ten seconds of CPU and more) is ended at either, and the page
is told which, in one line."""

from __future__ import annotations

import json
import subprocess
import sys
from multiprocessing import Pipe
from pathlib import Path

import pytest

from crslab.serve.page_process import Session, SessionLimits
from crslab.starters import starter_text

SLOW = Path(__file__).resolve().parent / "labs" / "sharing" / "slow_every_call.c"


@pytest.fixture(scope="module")
def golden(tmp_path_factory) -> Path:
    """Lab 1's golden file of 10 s on hands_off, no startup delay."""
    folder = tmp_path_factory.mktemp("golden")
    lab = folder / "lab1.c"
    lab.write_text(starter_text("lab1", "A"))
    path = folder / "golden.txt"
    r = subprocess.run([sys.executable, "-m", "crslab", "record", "--lab", lab, "--scenario", "hands_off",
                        "--no-startup-delay", "--duration", "10", "-o", path], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    return path


def checked(tmp_path: Path, golden: Path, limits: SessionLimits) -> dict:
    """The page's ``checked`` message for the slow lab against ``golden``, in a session with
    ``limits``."""
    ours, theirs = Pipe()
    session = Session(theirs, tmp_path / "session", limits)
    session.check({"lab": {"name": SLOW.name, "text": SLOW.read_text()},
                   "golden": {"name": golden.name, "text": golden.read_text()}})
    return json.loads(ours.recv_bytes()[1:])


def test_a_check_past_its_wall_time_ends_where_it_got_to(tmp_path, golden):
    msg = checked(tmp_path, golden, SessionLimits(check_wall_s=1.0, check_cpu_s=600.0, sandboxed=False))
    assert msg["type"] == "checked" and not msg["ok"]
    first = msg["report"].splitlines()[0]
    assert first.startswith("the check took more than this server's 1 s: its run was ended at t = ")
    assert float(first.rsplit("t = ", 1)[1].removesuffix(" s")) < 10.0


def test_a_check_past_its_cpu_time_is_ended_by_its_limit(tmp_path, golden):
    msg = checked(tmp_path, golden, SessionLimits(check_wall_s=600.0, check_cpu_s=1.0, sandboxed=False))
    assert msg["type"] == "checked" and not msg["ok"]
    first = msg["report"].splitlines()[0]
    assert first.startswith(f"{SLOW.name} used up its CPU-time limit (1 s) in lab() at tick ")
