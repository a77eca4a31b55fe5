"""A new output of a run is one file: this one. It defines a sink (every motor-board cut-out and
every expectation the run reports, and how many lines, scope rows and ticks reached it) and the
one row of :data:`crslab.cli.sink_options.SINK_OPTIONS` that gives ``crslab sim`` and ``crslab
debug`` its option; nothing else in crslab changes."""

from pathlib import Path

import pytest

from crslab.cli import main, sink_options
from crslab.cli.sink_options import SinkOption
from crslab.sinks.sink import Sink

SATURATING = Path(__file__).parent / "labs" / "saturating_gen_b.c"
"""Commands 4.5 units on joint 1 from 4.1 s for 2 s, then 0 (Piccolo: cut at 4.6 s, back at 6.1 s)."""
SCENARIO = """name = "cut"
end = 6.7

[[event]]
at = 4.5
kind = "expect"
motor_board_off = false

[[event]]
at = 5.0
kind = "expect"
motor_board_off = true

[[event]]
at = 6.0
kind = "expect"
motor_board_off = false
"""


class RunReport(Sink):
    """What a run reports, one line each, in a text file."""

    def __init__(self, path):
        self.file = open(path, "w")  # noqa: SIM115 - closed in close()
        self.lines = self.rows = 0
        self.reached = []

    def on_motor_board(self, tick, joint, off):
        self.file.write(f"motor board {'off' if off else 'on'} at {tick} (joint {joint})\n")

    def on_expectation(self, outcome):
        self.file.write(f"expectation at {outcome.tick}: {'met' if outcome.met else 'failed'}\n")

    def on_serial(self, tick, data):
        self.lines += data.count(b"\n")

    def on_log(self, columns):
        self.rows += len(columns["tick"])

    def on_reached(self, tick):
        self.reached.append(tick)

    def close(self):
        self.file.write(f"{self.lines} lines, {self.rows} scope rows, reached {self.reached[-1]}\n")
        self.file.close()


REPORT_OPTION = SinkOption("--run-report", "write what the run reports, one line each, to FILE",
                           lambda path, config: RunReport(path), writes="the run report", scope_rows=True)


@pytest.fixture
def with_report_option(monkeypatch):
    monkeypatch.setattr(sink_options, "SINK_OPTIONS", [*sink_options.SINK_OPTIONS, REPORT_OPTION])


def test_a_sink_defined_in_one_file_gets_everything_the_run_reports(with_report_option, tmp_path, capsys):
    scenario = tmp_path / "cut.toml"
    scenario.write_text(SCENARIO)
    report, transcript = tmp_path / "out" / "report.txt", tmp_path / "transcript.txt"
    status = main(["sim", "--fast", "--no-stdin", "--quiet", "--lab", str(SATURATING), "--scenario",
                   str(scenario), "--run-report", str(report), "-o", str(transcript)])
    err = capsys.readouterr().err
    assert status == 1, err  # the expectation at 6.0 s fails: the board is back only at 6.1 s
    said = report.read_text().splitlines()
    # what the Piccolo board does to 4.5 units on joint 1 from 4.1 s (docs/framework.md section 5)
    assert sorted(line for line in said if line.startswith("motor board")) == [
        "motor board off at 4600 (joint 1)", "motor board on at 6100 (joint 1)"]
    assert [line for line in said if line.startswith("expectation")] == [
        "expectation at 4500: met", "expectation at 5000: met", "expectation at 6000: failed"]
    # the lines the board printed (the transcript of the same run), a scope row per tick of 6.7 s
    lines = transcript.read_bytes().count(b"\n\r")
    assert lines > 0 and said[-1] == f"{lines} lines, 6700 scope rows, reached 6700"
    assert "crslab sim: expectation failed: t = 6.000 s: expected the motor board on, it was off" in err


def test_the_row_is_the_option_of_sim_and_debug_and_its_file_is_checked_first(with_report_option, tmp_path,
                                                                              capsys):
    for command in ("sim", "debug"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        assert "--run-report FILE" in capsys.readouterr().out
    status = main(["sim", "--fast", "--no-stdin", "--run-report", str(tmp_path)])
    assert status == 2
    assert capsys.readouterr().err == (f"crslab sim: {tmp_path}: is a directory; give a file name for "
                                       "the run report\n")


def test_without_the_row_there_is_no_such_option(capsys):
    with pytest.raises(SystemExit) as stopped:
        main(["sim", "--run-report", "x.txt"])
    assert stopped.value.code == 2 and "unrecognized arguments: --run-report x.txt" in capsys.readouterr().err
