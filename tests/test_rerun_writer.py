"""--rrd through the writer process forked at the ``crslab`` command's start
(crslab/sinks/rerun_writer.py): the same recording as the in-process sink writes, the crslab
process never importing rerun, and a recording that cannot be finished is one line, status 2,
with the transcript kept."""

import os
import subprocess
import sys
from pathlib import Path

import pyarrow as pa
import pytest
from rerun.chunk import RrdReader

from crslab.sinks.rerun_writer import wants_writer

ROOT = Path(__file__).resolve().parents[1]
RUN = ["sim", "--fast", "--no-stdin", "--duration", "5"]  # past 4.1 s: lab() prints, the arm moves

AS_THE_COMMAND = """
import sys
from crslab.cli import main
sys.argv = ["crslab", *sys.argv[1:]]
status = main()  # argv from sys.argv: the crslab command, which forks the writer for --rrd
print("rerun imported" if "rerun" in sys.modules else "rerun not imported")
sys.exit(status)
"""

IN_PROCESS = """
import sys
from crslab.cli import main
sys.exit(main(sys.argv[1:]))  # argv given: crslab as a library, RerunSink in this process
"""

WRITER_KILLED = """
import os, signal, sys
from crslab.cli import main
from crslab.sinks import rerun_writer

start = rerun_writer.start_writer

def start_then_kill(argv):
    start(argv)
    writer = rerun_writer._writer[0]
    os.kill(writer.pid, signal.SIGKILL)
    os.waitpid(writer.pid, 0)  # dead before the run starts

rerun_writer.start_writer = start_then_kill
sys.argv = ["crslab", *sys.argv[1:]]
sys.exit(main())
"""


def crslab(probe, *args):
    return subprocess.run([sys.executable, "-c", probe, *map(str, args)], cwd=ROOT, capture_output=True,
                          text=True, stdin=subprocess.DEVNULL)


def contents(path):
    """Every entity's rows, static and timed, without rerun's row ids: {entity: {column: values}}."""
    tables = {}
    for chunk in RrdReader(path).stream():
        key = chunk.entity_path + (" static" if chunk.is_static else "")
        tables.setdefault(key, []).append(pa.Table.from_batches([chunk.to_record_batch()]))
    out = {}
    for key, parts in tables.items():
        table = pa.concat_tables(parts, promote_options="default").drop_columns(["rerun.controls.RowId"])
        if "sim_time" in table.column_names:
            table = table.sort_by("sim_time")
        out[key] = table.to_pydict()
    return out


def test_the_writer_process_writes_the_same_recording_and_the_crslab_process_never_imports_rerun(tmp_path):
    by_writer = crslab(AS_THE_COMMAND, *RUN, "--rrd", tmp_path / "writer.rrd")
    assert by_writer.returncode == 0, by_writer.stderr
    assert by_writer.stdout.splitlines()[-1] == "rerun not imported"  # so the writer wrote it
    in_process = crslab(IN_PROCESS, *RUN, "--rrd", tmp_path / "in_process.rrd")
    assert in_process.returncode == 0, in_process.stderr
    written, expected = contents(tmp_path / "writer.rrd"), contents(tmp_path / "in_process.rrd")
    assert "/serial" in expected and "/arm/forearm" in expected and "/scopes/simulink static" in expected
    assert len(expected["/scopes/motor_angle"]["sim_time"]) == 5000  # a row per tick
    assert written == expected


def check_unfinished(r, tmp_path, why):
    assert r.returncode == 2, r.stderr
    err = r.stderr.splitlines()
    assert err[-1].startswith("crslab sim: could not finish writing ") and why in err[-1], err
    assert not any("Traceback" in line for line in err), r.stderr
    plain = crslab(IN_PROCESS, *RUN, "--transcript", tmp_path / "plain.bin")
    assert plain.returncode == 0, plain.stderr
    kept = (tmp_path / "run.bin").read_bytes()
    assert kept.count(b"\n\r") == 6 and kept == (tmp_path / "plain.bin").read_bytes()


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
def test_a_recording_the_writer_cannot_write_is_one_line_status_2_and_the_transcript_is_kept(tmp_path):
    r = crslab(AS_THE_COMMAND, *RUN, "--rrd", "/dev/full", "--transcript", tmp_path / "run.bin")
    check_unfinished(r, tmp_path, "/dev/full: ")
    assert "No space left on device" in r.stderr.splitlines()[-1]


def test_a_writer_that_died_is_one_line_status_2_and_the_transcript_is_kept(tmp_path):
    r = crslab(WRITER_KILLED, *RUN, "--rrd", tmp_path / "run.rrd", "--transcript", tmp_path / "run.bin")
    check_unfinished(r, tmp_path, "the rerun writer process ended early")


def test_only_a_run_command_with_rrd_forks_the_writer():
    assert wants_writer(["sim", "lab.c", "--rrd", "run.rrd"]) and wants_writer(["debug", "--rrd=run.rrd"])
    assert not wants_writer(["sim", "--rerun"]) and not wants_writer(["sim", "--", "--rrd"])
    assert not wants_writer(["scope", "--rrd", "x.rrd"]) and not wants_writer(["--version"])


SERVE_RECORDER = """
import sys
from pathlib import Path
from crslab.run.assemble import make_config, run_kept
from crslab.sinks.rerun_writer import RecorderSink

out = Path(sys.argv[1])
config = make_config("csrc/labs/lab2_square_pid.c", log=True, world="contest")  # the world's columns too
recorder = RecorderSink(out / "page.csv", out / "page.rrd", "lab2_square_pid.c", config.world)  # forked now
from crslab.sinks.csv_file import CsvSink
from crslab.sinks.rerun_scopes import RerunSink

in_process = [CsvSink(out / "cli.csv", world=True),
              RerunSink(rrd_path=out / "cli.rrd", name="lab2_square_pid.c", world=config.world)]
assert run_kept(config, 5000, [recorder, *in_process]).status == "ok"
for sink in [recorder, *in_process]:
    sink.close()
"""


def test_serves_recorder_writes_the_csv_and_recording_that_csv_and_rrd_write(tmp_path):
    """crslab serve's downloads (RecorderSink, a writer forked when the run starts) are --csv's and
    --rrd's files of the same run: the CSV byte for byte, the recording entity by entity."""
    r = crslab(SERVE_RECORDER, tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "page.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    assert (tmp_path / "cli.csv").read_bytes().count(b"\n") == 5001  # the header and a row per tick
    written, expected = contents(tmp_path / "page.rrd"), contents(tmp_path / "cli.rrd")
    assert "/scopes/scale" in expected and "/arm/forearm" in expected and "/serial" in expected
    assert written == expected


def test_a_recorder_whose_writer_died_names_its_files_when_closed(tmp_path):
    from crslab.sinks.rerun_writer import RecorderSink
    from crslab.sinks.sink import SinkError

    recorder = RecorderSink(tmp_path / "run.csv", tmp_path / "run.rrd", "lab.c")
    os.kill(recorder.writer.pid, 9)
    with pytest.raises(SinkError) as caught:
        recorder.close()
    files = f"{tmp_path / 'run.csv'} and {tmp_path / 'run.rrd'}"
    assert str(caught.value) == f"could not finish writing {files}: the rerun writer process ended early"
