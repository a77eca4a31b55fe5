"""How a run ended: one status set for sim, record, check and grade, each status with the exit
status of README's table and the grade class of docs/regression.md's."""

import re
from pathlib import Path

import pytest

from crslab.regress.grade import Grade, counts_line
from crslab.run.status import ExitStatus, GradeClass, RunResult, RunStatus

ROOT = Path(__file__).resolve().parents[1]


def table_rows(text, header):
    """The first-column -> second-column pairs of the markdown table under ``header``."""
    body = text.split(header, 1)[1].split("\n\n", 1)[0]
    return [[cell.strip() for cell in row.strip("|").split("|")] for row in body.splitlines()[2:]]


def test_every_exit_status_is_a_row_of_the_readmes_table():
    rows = table_rows((ROOT / "README.md").read_text(), "| exit status | meaning |")
    assert [int(r[0]) for r in rows] == [int(e) for e in ExitStatus]


@pytest.mark.parametrize("status, exit_status, words", [
    ("ok", 0, "ended normally"), ("unmet", 1, "an expectation of the scenario failed"),
    ("crashed", 3, "crashed"), ("exited", 3, "exit()"), ("hung", 4, "hung"),
    ("nan", 5, "NaN"), ("output-limit", 6, "--max-output-mb"), ("interrupted", 130, "Ctrl-C"),
    ("no-lab", 2, "does not compile"), ("build-error", 2, "does not compile"),
    ("unfit", 2, "malformed scenario"), ("timeout", 4, "hung")])
def test_each_status_exits_as_the_readme_says(status, exit_status, words):
    rows = dict((int(r[0]), r[1]) for r in table_rows((ROOT / "README.md").read_text(),
                                                      "| exit status | meaning |"))
    assert RunStatus(status).exit_status == exit_status and words in rows[exit_status]


def test_each_status_grades_as_docs_regression_says():
    rows = {r[0]: r[1] for r in table_rows((ROOT / "docs" / "regression.md").read_text(),
                                           "| result | meaning | JUnit |")}
    graded = {s: s.graded(matched=False) for s in RunStatus if s is not RunStatus.FORBIDDEN}
    assert RunStatus.OK.graded(matched=True) == "pass" and graded[RunStatus.OK] == "mismatch"
    no_compile = {RunStatus.NO_LAB, RunStatus.BUILD_ERROR}
    assert {s for s, g in graded.items() if g == "does not compile"} == no_compile
    assert {s for s, g in graded.items() if g == "hung"} == {RunStatus.HUNG, RunStatus.TIMEOUT}
    assert graded[RunStatus.UNFIT] == "mismatch" and "does not watch" in rows["mismatch"]
    for status in (RunStatus.CRASHED, RunStatus.EXITED, RunStatus.OUTPUT_LIMIT):
        assert graded[status] == "crashed"
    assert "exit()" in rows["crashed"] and "runaway output" in rows["crashed"]
    assert "--timeout" in rows["hung"] and "no `lab()`" in rows["does not compile"]
    # a failed expectation is its own class, whatever the transcript
    assert graded[RunStatus.UNMET] == RunStatus.UNMET.graded(matched=True) == "unmet"
    assert "expectation" in rows["unmet"] and "whatever its transcript" in rows["unmet"]


def test_forbidden_exits_as_a_crash_and_is_counted_only_when_it_happens():
    assert RunStatus.FORBIDDEN.exit_status == ExitStatus.CRASHED
    assert RunStatus.FORBIDDEN.graded(matched=True) == GradeClass.FORBIDDEN

    def grade(status):
        return Grade(Path("a.c"), status.graded(matched=True), "", RunResult(status))

    assert counts_line([grade(RunStatus.OK), grade(RunStatus.HUNG)]) == (
        "2 submissions: 1 pass, 0 mismatch, 0 does not compile, 0 crashed, 1 hung")
    assert counts_line([grade(RunStatus.FORBIDDEN)]).endswith("0 hung, 1 forbidden")
    assert counts_line([grade(RunStatus.UNMET)]) == (
        "1 submissions: 0 pass, 0 mismatch, 1 unmet, 0 does not compile, 0 crashed, 0 hung")


def test_statuses_keep_their_names_in_text_and_json():
    import json

    assert json.dumps({"status": RunStatus.OUTPUT_LIMIT}) == '{"status": "output-limit"}'
    assert [str(s) for s in RunStatus] == ["ok", "unmet", "crashed", "exited", "hung", "forbidden", "nan",
                                          "output-limit", "interrupted", "no-lab", "build-error", "unfit",
                                          "timeout"]
    assert re.fullmatch(r"[a-z-]+", f"{RunStatus.NO_LAB}")


def test_a_run_result_is_one_flat_record():
    r = RunResult(RunStatus.HUNG, 5100, "lab.c hung", calls=[(4100, b"1.00\n\r"), (4600, b"2.")])
    assert (r.ok, r.exit_status, r.transcript, r.lines()) == (False, 4, b"1.00\n\r2.", ["1.00", "2."])
