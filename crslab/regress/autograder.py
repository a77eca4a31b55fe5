"""Grading one submission for an autograder platform: its tests (a scenario each, with points)
and the platform's results file.

- Gradescope (``/autograder/results/results.json``): ``score`` (points), ``execution_time``,
  ``output``, and ``tests`` with ``name``, ``score``, ``max_score``, ``status`` (passed or failed),
  ``output``; see docs/autograder.md for the specification it follows.
- PrairieLearn external grading (``/grade/results/results.json``): ``gradable``, ``score`` (0..1),
  ``message``, ``output``, and ``tests`` with ``name``, ``description``, ``points``,
  ``max_points``, ``message``, ``output``. A submission that does not compile is not gradable
  (``format_errors`` says why), so the student keeps the attempt, as PrairieLearn intends.

A tests file (``--tests``) lists the tests::

    [[test]]
    name = "Lab 1 on the tour"        # optional: default the scenario's name
    scenario = "tour"                 # a built-in or a file (relative to this file)
    duration = 12.0                   # optional: simulated seconds (default: the scenario's end)
    points = 6

>>> tests = parse_tests('[[test]]\\nscenario = "tour"\\npoints = 2\\n', Path("t.toml"))
>>> tests
[PlatformTest(name='tour', scenario='tour', duration_s=None, points=2.0)]
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from crslab.output_paths import with_parent
from crslab.regress.grade import Grade
from crslab.run.status import GradeClass
from crslab.scenario.event import LONGEST_S
from crslab.scenario.file_table import ScenarioError
from crslab.scenario.load import resolve
from crslab.toml_file import TomlFile
from crslab.untrusted_text import for_terminal, for_text

PLATFORMS = ("gradescope", "prairielearn")
OUTPUT_CHARS = 4000
"""Most characters of a test's output (the platforms show it folded; PrairieLearn's whole file
must stay under 1 MB)."""


@dataclass(frozen=True)
class PlatformTest:
    """One test: a scenario the submission must print the reference's transcript on."""

    name: str
    scenario: str
    duration_s: float | None
    points: float


@dataclass(frozen=True)
class Outcome:
    """How the submission did on one test."""

    test: PlatformTest
    grade: Grade

    @property
    def passed(self) -> bool:
        return self.grade.grade == GradeClass.PASS

    @property
    def points(self) -> float:
        return self.test.points if self.passed else 0.0

    def output(self) -> str:
        """What the student reads: the grade, the report (first differing lines or the crash), and
        the last lines the submission printed; what the submission controls is escaped
        (:mod:`crslab.untrusted_text`), as in crslab grade's reports."""
        g = self.grade
        parts = [g.verdict]
        report = g.report
        if report and report != g.detail:
            parts.append(report)
        lines = g.result.lines()
        if lines:
            shown = lines[-15:]
            parts.append(f"the last {len(shown)} of the {len(lines)} lines it printed:\n" + "\n".join(shown))
        return _excerpt(for_text("\n\n".join(parts)))


def _excerpt(text: str) -> str:
    return text if len(text) <= OUTPUT_CHARS else text[: OUTPUT_CHARS - 30] + "\n... (output cut here)"


class BadTestsFile(ValueError):
    """A tests file that cannot be used; the message names the file, line and key."""


def parse_tests(text: str, path: Path) -> list[PlatformTest]:
    """The tests of a tests file's ``text`` (read from ``path``); scenario files are resolved
    relative to the tests file."""
    return _tests(TomlFile.parse(text, str(path), BadTestsFile), path)


def load_tests(path: Path) -> list[PlatformTest]:
    """The tests of the tests file ``path``, read through the checked reader."""
    return _tests(TomlFile.read(path, "tests file", BadTestsFile), path)


def _tests(doc: TomlFile, path: Path) -> list[PlatformTest]:
    tables = doc.data.get("test")
    if set(doc.data) - {"test"} or not isinstance(tables, list) or not tables:
        raise BadTestsFile(
            f"{path}: expected one or more [[test]] tables (scenario, points, optional name "
            "and duration) and nothing else"
        )
    out = []
    try:
        for r in doc.tables("test"):
            r.check_keys({"name", "scenario", "duration", "points"})
            scenario = r.text("scenario")
            local = path.parent / scenario
            if local.is_file():
                scenario = str(local)
            resolve(scenario)  # a missing scenario is said now, naming it
            duration = r.number("duration", minimum=0.001, maximum=LONGEST_S) if "duration" in r else None
            name = r.text("name") if "name" in r else Path(scenario).stem
            out.append(PlatformTest(name, scenario, duration, r.number("points", minimum=0.0)))
    except ScenarioError as exc:
        raise BadTestsFile(str(exc)) from None
    return out


def gradescope_results(results: Sequence[Outcome], *, seconds: float, note: str = "") -> dict:
    """Gradescope's results.json for one submission."""
    total = sum(r.points for r in results)
    possible = sum(r.test.points for r in results)
    summary = (
        note
        or f"{sum(r.passed for r in results)} of {len(results)} tests passed: "
        f"{total:g} of {possible:g} points"
    )
    return {
        "score": total,
        "execution_time": round(seconds, 3),
        "output": summary,
        "tests": [
            {
                "name": r.test.name,
                "score": r.points,
                "max_score": r.test.points,
                "status": "passed" if r.passed else "failed",
                "output": r.output(),
            }
            for r in results
        ],
    }


def prairielearn_results(results: Sequence[Outcome], *, note: str = "") -> dict:
    """PrairieLearn's results.json for one submission (score from 0 to 1)."""
    not_compiling = [r for r in results if r.grade.grade == GradeClass.DOES_NOT_COMPILE]
    if not_compiling:
        g = not_compiling[0].grade
        return {
            "gradable": False,
            "format_errors": [for_terminal(g.detail)],
            "message": f"{for_terminal(g.path.name)} does not compile",
            "output": _excerpt(for_text(g.report)),
        }
    total = sum(r.points for r in results)
    possible = sum(r.test.points for r in results)
    return {
        "gradable": True,
        "score": total / possible if possible else 0.0,
        "message": note or f"{sum(r.passed for r in results)} of {len(results)} tests passed",
        "output": "\n".join(f"{r.test.name}: {r.grade.grade}" for r in results),
        "tests": [
            {
                "name": r.test.name,
                "description": _describe(r.test),
                "points": r.points,
                "max_points": r.test.points,
                "message": for_terminal(r.grade.verdict),
                "output": r.output(),
            }
            for r in results
        ],
    }


def not_one_submission(platform: str, found: Sequence[Path], folder: Path) -> dict:
    """The results file when the folder does not hold exactly one lab file: no points, and why."""
    names = ", ".join(for_terminal(p.name) for p in found) or "none"
    why = f"expected exactly one lab file (.c or .cpp) in the submission, found {len(found)}: {names}"
    if platform == "gradescope":
        return {"score": 0.0, "output": why, "tests": []}
    return {"gradable": False, "format_errors": [why], "message": why}


def _describe(test: PlatformTest) -> str:
    how = f" for {test.duration_s:g} s" if test.duration_s is not None else ""
    return f"runs on scenario {Path(test.scenario).stem}{how} and must print what the reference prints"


def write_results(path: Path, results: dict) -> None:
    """Write a results file (its folder is made when missing: PrairieLearn does not make it)."""
    with_parent(path).write_text(json.dumps(results, indent=2) + "\n")
