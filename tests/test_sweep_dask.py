"""Sweeps and grading on a Dask cluster give the tables the local pool gives, row for row; a
worker that dies is a row with its status; an unreachable scheduler is one line. The clusters
start in this process and listen on the loopback only."""

import csv
import logging
import os
import shutil
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from crslab.cli import main
from tests.waiting import GUARD_S, LineWatcher, wait_exit

pytest.importorskip("distributed")

LABS = Path(__file__).parent / "labs"
REFERENCE = Path(__file__).resolve().parents[1] / "csrc" / "labs" / "lab1_kinematics.c"
SWEEP = [
    "sweep",
    "--lab",
    LABS / "sweep_pd.c",
    "--scenario",
    "hands_off",
    "--duration",
    "1",
    "--no-startup-delay",
    "--vary",
    "friction=0.5:1.5",
    "--vary",
    "payload_kg=0:2",
    "--samples",
    "8",
    "--seed",
    "7",
]


@pytest.fixture(scope="module")
def cluster():
    """One in-process LocalCluster of 2 workers on the loopback, shared by this module's tests."""
    from dask.distributed import LocalCluster

    with LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=False,
        protocol="tcp",
        host="127.0.0.1",
        dashboard_address="127.0.0.1:0",
        silence_logs=logging.ERROR,
    ) as c:
        assert c.scheduler_address.startswith("tcp://127.0.0.1:")
        import psutil  # a dependency of distributed

        listening = {
            conn.laddr.ip for conn in psutil.Process().net_connections("inet") if conn.status == "LISTEN"
        }
        assert listening == {"127.0.0.1"}  # the loopback only
        yield c


def crslab(*args):
    return main([str(a) for a in args])


@pytest.fixture(scope="module")
def local_table(tmp_path_factory):
    """The sweep's table from the local pool (two processes), run once for the module's tests."""
    local = tmp_path_factory.mktemp("sweep") / "local.csv"
    assert crslab(*SWEEP, "--jobs", "2", "-o", local) in (0, 1)
    return local


def test_eight_seeded_samples_give_identical_tables_locally_and_on_dask(tmp_path, cluster, capsys,
                                                                      local_table):
    local, dask_local, dask_remote = local_table, tmp_path / "dask.csv", tmp_path / "remote.csv"
    assert crslab(*SWEEP, "--dask", "local:2", "-o", dask_local) in (0, 1)
    assert crslab(*SWEEP, "--dask", cluster.scheduler_address, "-o", dask_remote) in (0, 1)
    assert local.read_bytes() == dask_local.read_bytes() == dask_remote.read_bytes()
    with local.open() as f:
        rows = list(csv.DictReader(f))
    assert [r["sample"] for r in rows] == [str(i) for i in range(8)]
    assert {r["status"] for r in rows} == {"ok"}
    assert len({r["friction"] for r in rows}) == 8  # eight different arms
    err = capsys.readouterr().err
    assert "on a local Dask cluster of 2 workers" in err and "Traceback" not in err
    # the same again on one worker: the same table (the worker count never matters)
    one = tmp_path / "one.csv"
    assert crslab(*SWEEP, "--jobs", "1", "-o", one) in (0, 1)
    assert one.read_bytes() == local.read_bytes()


def test_parquet_holds_the_same_rows(tmp_path, cluster, local_table):
    import pyarrow.parquet as pq

    csv_file, parquet = local_table, tmp_path / "r.parquet"
    assert crslab(*SWEEP, "--dask", cluster.scheduler_address, "-o", parquet) in (0, 1)
    table = pq.read_table(parquet).to_pylist()
    with csv_file.open() as f:
        rows = list(csv.DictReader(f))
    assert [r["sample"] for r in table] == list(range(8))
    for p, c in zip(table, rows, strict=True):
        assert repr(p["friction"]) == c["friction"] and p["status"] == c["status"]
        assert repr(p["theta2motor_final_rad"]) == c["theta2motor_final_rad"]


def test_grading_on_dask_is_grading_without_it(tmp_path, cluster, capsys):
    subs = tmp_path / "subs"
    subs.mkdir()
    shutil.copy(LABS / "lab1_own_ik.c", subs / "good.c")
    text = (LABS / "lab1_own_ik.c").read_text()
    (subs / "wrong.c").write_text(text.replace("atan2(-s_in, r_in)", "atan2(s_in, r_in)"))
    shutil.copy(LABS / "does_not_compile.c", subs / "broken.c")
    shutil.copy(LABS / "crash_after_5s.c", subs / "crash.c")
    outs = {}
    for how in (["--jobs", "2"], ["--dask", "local:2"], ["--dask", cluster.scheduler_address]):
        out = tmp_path / how[-1].replace(":", "_").replace("/", "_")
        assert crslab("grade", subs, "--reference", REFERENCE, "--duration", "6", "--out", out, *how) == 1
        outs[how[-1]] = out
    first, *others = outs.values()

    def graded(out):  # every column but the wall-clock seconds
        with (out / "grades.csv").open() as f:
            return [{k: v for k, v in row.items() if k != "seconds"} for row in csv.DictReader(f)]

    assert [r["result"] for r in graded(first)] == ["does not compile", "crashed", "pass", "mismatch"]
    for out in others:
        assert graded(out) == graded(first)
        assert (out / "summary.txt").read_text() == (first / "summary.txt").read_text()
        for name in ("good.c", "wrong.c", "crash.c", "lab1_kinematics.c.reference"):
            assert (out / "transcripts" / f"{name}.txt").read_bytes() == (
                first / "transcripts" / f"{name}.txt"
            ).read_bytes()


def test_an_unreachable_scheduler_is_one_line(tmp_path, capsys):
    import socket

    with socket.socket() as s:  # a loopback port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    status = crslab(
        *SWEEP, "--dask", f"tcp://127.0.0.1:{port}", "--dask-timeout", "1", "-o", tmp_path / "r.csv"
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1, err
    assert err[0].startswith(
        f"crslab sweep: --dask tcp://127.0.0.1:{port}: the Dask scheduler cannot be reached"
    )
    assert not (tmp_path / "r.csv").exists() and not list(tmp_path.iterdir())
    status = crslab(
        "grade",
        LABS,
        "--reference",
        REFERENCE,
        "--dask",
        f"tcp://127.0.0.1:{port}",
        "--dask-timeout",
        "1",
        "--out",
        tmp_path / "g",
    )
    assert status == 2 and "the Dask scheduler cannot be reached" in capsys.readouterr().err


def test_a_worker_that_dies_is_a_row_with_its_status(tmp_path):
    """The Dask worker running sample 0 is killed; Dask may not retry it (allowed failures 0): the
    sweep still ends, with that sample's row saying so."""
    from dask.distributed import Client, LocalCluster
    from distributed.diagnostics.plugin import SchedulerPlugin

    processing = threading.Event()

    class Watch(SchedulerPlugin):
        def transition(self, key, start, finish, *args, **kwargs):
            if str(key).startswith("crslab-") and finish == "processing":
                processing.set()

    with (
        LocalCluster(
            n_workers=1,
            threads_per_worker=1,
            processes=True,
            protocol="tcp",
            host="127.0.0.1",
            dashboard_address="127.0.0.1:0",
            silence_logs=logging.ERROR,
        ) as c,
        Client(c) as client,
    ):
        c.scheduler.allowed_failures = 0
        c.scheduler.add_plugin(Watch())
        [pid] = client.run(os.getpid).values()
        out = tmp_path / "r.csv"
        proc = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "crslab",
                "sweep",
                "--lab",
                LABS / "hang_after_5s.c",
                "--scenario",
                "hands_off",
                "--deadline",
                "100",
                "--vary",
                "friction=1:1",
                "--samples",
                "1",
                "--dask",
                c.scheduler_address,
                "-o",
                out,
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        err = LineWatcher(proc.stderr, "crslab sweep's stderr")
        assert processing.wait(GUARD_S), "the sweep's task never reached the worker"
        os.kill(pid, signal.SIGKILL)
        assert wait_exit(proc, "its worker was killed") == 1, err.all()
        with out.open() as f:
            [row] = list(csv.DictReader(f))
        assert row["status"] == "crashed" and row["passed"] == "False"
        assert row["message"] == "sample 0: the Dask workers running it died"
        assert "Traceback" not in err.all()
        proc.stdout.close()
