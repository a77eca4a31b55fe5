"""Every report crslab grade writes, fed every hostile file name and printed text at once: what a
submission controls (its file's name, what its lab printed, the diagnosis quoting either) stays
inert wherever it lands (issue 31, the rest of the boundary).

The hostile texts: ANSI escape sequences (a colour, a line erase, a cursor move), a carriage
return, bidirectional controls (U+202E), a non-character (U+FFFE), a zero-width space, NUL, bytes
that are not UTF-8, newlines, and cells that start a spreadsheet formula (``=``, ``+``, ``-``,
``@``). The reports are built here from real runs' results (graded by ``grade_result``, compared
by ``compare``), not by running labs: each writer is checked for what it lets through.
"""

from __future__ import annotations

import csv
import io
import json
import unicodedata
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from json_strings import json_strings

from crslab.regress import autograder as ag
from crslab.regress.grade import Grade, grade_result, summary_table, write_csv, write_junit_grades
from crslab.run.status import GradeClass, RunResult, RunStatus

HOSTILE = ["\x1b[2K\r\x1b[32mpass\x1b[0m", "evil\u202egnp.c", "non\ufffechar", "zero\u200bwidth",
           "nul\x00byte", "bell\x07", "\x9b31m", "two\nlines", "=HYPERLINK(\"http://x.example\",\"pass\")",
           "+1+cmd", "-2-cmd", "@SUM(A1)"]
"""Texts a submission controls, each on its own (names, printed lines, diagnoses)."""
NAMES = [f"{t}.c" if not t.endswith(".c") else t for t in HOSTILE if "\x00" not in t] + ["=1.c", "@x.c"]
"""File names (a file name holds any byte but NUL and ``/``)."""
FORMULA = ("=", "+", "-", "@", "\t", "\r")


def unsafe(text: str, newlines: bool = False) -> list[str]:
    """The characters of ``text`` no report may hold raw: controls (newlines unless allowed),
    C1 controls, bidi and other format characters, line separators, surrogates, non-characters."""
    bad = []
    for ch in text:
        code = ord(ch)
        if ch == "\n" and newlines or ch == "\t":
            continue
        if (code < 0x20 or 0x7F <= code <= 0x9F or 0xD800 <= code <= 0xDFFF or (code & 0xFFFE) == 0xFFFE
                or 0xFDD0 <= code <= 0xFDEF or unicodedata.category(ch) in ("Cf", "Zl", "Zp")):
            bad.append(ch)
    return bad


def hostile_printout() -> bytes:
    """What a hostile lab printed: every hostile text as a line, and bytes that are not UTF-8."""
    return b"".join(t.encode() + b"\n\r" for t in HOSTILE) + b"\xff\xfe raw bytes\n\r"


@pytest.fixture(scope="module")
def grades() -> list[Grade]:
    reference = RunResult(RunStatus.OK, 5000, calls=[(1000 + i, b"0.00 0.00 0.00\n\r") for i in range(14)])
    out = []
    for i, name in enumerate(NAMES):
        path = Path("class") / name
        printed = hostile_printout()
        kind = i % 4
        if kind == 0:  # ran to its end, printed hostile text: a mismatch quoting it
            result = RunResult(RunStatus.OK, 5000, calls=[(1000, printed)], lab_file=path)
        elif kind == 1:  # refused by the sandbox: the diagnosis quotes the path it tried, and its name
            result = RunResult(RunStatus.FORBIDDEN, 5123, f"{name} was stopped by the sandbox: it tried to "
                               f"open /tmp/{HOSTILE[i % len(HOSTILE)]} for reading", calls=[(1000, printed)],
                               lab_file=path)
        elif kind == 2:  # does not compile: the compiler quotes its source
            result = RunResult(RunStatus.BUILD_ERROR, 0, f"{name} does not compile",
                               details=f"{name}:3:1: error: unknown type name '{''.join(HOSTILE)}'",
                               lab_file=path)
        else:  # crashed after printing
            result = RunResult(RunStatus.CRASHED, 4000, f"{name} read or wrote outside its memory",
                               calls=[(1000, printed)], lab_file=path)
        out.append(grade_result(result, reference))
    return out


def test_the_runs_are_graded_as_their_ends_say(grades):
    assert [g.grade for g in grades[:4]] == [GradeClass.MISMATCH, GradeClass.FORBIDDEN,
                                              GradeClass.DOES_NOT_COMPILE, GradeClass.CRASHED]
    assert any("\x1b" in g.report for g in grades)  # the raw reports do hold the hostile text


def test_grades_csv_cells_are_one_line_without_controls_and_never_start_a_formula(grades, tmp_path):
    write_csv(tmp_path / "grades.csv", grades)
    with (tmp_path / "grades.csv").open(newline="") as f:
        rows = list(csv.reader(f))
    assert len(rows) == 1 + len(grades)  # no name or detail broke a row
    cells = [cell for row in rows for cell in row]
    assert [c for c in cells if unsafe(c)] == []
    assert [c for c in cells if c.startswith(FORMULA)] == []
    names = [row[0] for row in rows[1:]]
    # each name is there, escaped visibly; a formula's gets a leading quote
    assert "'=1.c" in names and "'@x.c" in names and "'+1+cmd.c" in names and "'-2-cmd.c" in names
    assert "evil\\u202egnp.c" in names and "two\\x0alines.c" in names and "non\\ufffechar.c" in names


def test_junit_is_valid_xml_holding_no_control(grades, tmp_path):
    write_junit_grades(tmp_path / "junit.xml", grades, "lab1")
    root = ET.parse(tmp_path / "junit.xml").getroot()  # parses: XML 1.0 holds every character written
    cases = root.findall(".//testcase")
    assert len(cases) == len(grades)
    texts = [v for node in root.iter() for v in [*node.attrib.values(), node.text or ""]]
    assert [t for t in texts if unsafe(t, newlines=True)] == []
    assert {c.get("name") for c in cases} >= {"\\x1b[2K\\x0d\\x1b[32mpass\\x1b[0m.c", "evil\\u202egnp.c"}
    failures = [f.text for f in root.iter("failure")]
    assert any("\\x1b[2K" in t for t in failures)  # the printed text is shown, escaped


def test_the_terminal_summary_shows_every_escape_and_keeps_one_row_each(grades):
    out = io.StringIO()
    summary_table(grades, out)
    text = out.getvalue()
    assert unsafe(text, newlines=True) == []
    assert len(text.splitlines()) == 1 + len(grades) + 1  # header, a row each, the counts
    assert "\\x1b[2K\\x0d\\x1b[32mpass\\x1b[0m.c" in text and "evil\\u202egnp.c" in text


@pytest.mark.parametrize("platform", ["gradescope", "prairielearn"])
def test_an_autograders_results_hold_no_control_for_the_student_to_see(grades, platform, tmp_path):
    """What Gradescope and PrairieLearn show the student (their results file's strings, once the
    platform parses the JSON) holds the hostile text escaped, as the reports do."""
    test = ag.PlatformTest("tour", "tour", None, 10.0)
    for g in grades:
        outcomes = [ag.Outcome(test, g)]
        results = (ag.gradescope_results(outcomes, seconds=1.0) if platform == "gradescope"
                   else ag.prairielearn_results(outcomes))
        ag.write_results(tmp_path / "results.json", results)
        parsed = json.loads((tmp_path / "results.json").read_text())
        strings = json_strings(parsed)
        assert [s for s in strings if unsafe(s, newlines=True)] == [], g.path.name
    missing = ag.not_one_submission(platform, [Path("class") / n for n in NAMES[:3]], Path("class"))
    assert [s for s in json_strings(missing) if unsafe(s, newlines=True)] == []
    assert "\\x1b[2K" in json.dumps(missing)  # the name is there, escaped


