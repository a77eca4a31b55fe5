"""Grade a class by the contest's scorecard (``crslab grade DIR --contest``): every submission runs
in the contest world (as in :mod:`crslab.regress.grade`: a process of its own, a private copy, the
sandbox) and is scored by :func:`crslab.contest.scorecard.score`; no reference lab. A TA's
leaderboard: the table ranks by tasks done, then by time; ``grades.csv`` has a column per task and
the time; ``junit.xml`` a case per submission and task.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO

from crslab.contest.scorecard import Scorecard, ScorecardError, score
from crslab.regress.junit import Case, write_junit
from crslab.run.status import RunResult, RunStatus
from crslab.untrusted_text import for_csv, for_terminal

TASKS = Scorecard.TASKS


@dataclass(frozen=True)
class ContestGrade:
    """One submission's run and its card (None when it did not run to a log: then ``why``)."""

    path: Path
    result: RunResult
    card: Scorecard | None
    why: str = ""

    @property
    def result_word(self) -> str:
        """``complete`` (all four tasks), ``N of 4``, or how the run failed (``does not compile``, ...)."""
        if self.card is None:
            return str(self.result.status.graded(matched=False)) if self.result.status is not RunStatus.OK \
                else "no log"
        return "complete" if self.card.done == 4 else f"{self.card.done} of 4"

    @property
    def ranking(self) -> tuple:
        """Sort key: more tasks done first, then the shorter time, then the name."""
        done = self.card.done if self.card is not None else -1
        time_s = self.card.time_s if self.card is not None and self.card.time_s is not None else float("inf")
        return (-done, time_s, self.path.name)


def grade_contest(result: RunResult, world: Any) -> ContestGrade:
    """Score one submission's run (its scope log) in ``world``; the log is not kept."""
    path = result.lab_file or Path("?")
    slim = _without_log(result)
    if result.status is not RunStatus.OK and not result.log:
        return ContestGrade(path, slim, None, (result.message or str(result.status)).splitlines()[0])
    if not result.log:
        return ContestGrade(path, slim, None, "the run kept no scope log")
    try:
        card = score(result.log, world)
    except ScorecardError as exc:
        return ContestGrade(path, slim, None, str(exc))
    why = "" if result.status is RunStatus.OK else (result.message or str(result.status)).splitlines()[0]
    return ContestGrade(path, slim, card, why)


def _without_log(result: RunResult) -> RunResult:
    import dataclasses

    return dataclasses.replace(result, log=None)


def _task_cells(card: Scorecard | None) -> list[str]:
    if card is None:
        return [""] * 15
    d = card.as_dict()["tasks"]
    p, o, g, e = d["peg"], d["obstacle"], d["groove"], d["egg"]
    left = "" if g["left_at"] is None else f"{g['left_at'][0]:.4f} {g['left_at'][1]:.4f}"
    cells = [p["done"], p["depth_m"], p["held_s"], o["done"], o["touched"], g["done"], g["share"],
             g["max_side_force_n"], left, e["done"], e["peak_g"], e["in_band_s"], e["broken"],
             card.done, "" if card.time_s is None else f"{card.time_s:.3f}"]
    return [str(int(c)) if isinstance(c, bool) else str(c) for c in cells]


CSV_COLUMNS = ["submission", "result", "peg_done", "peg_depth_m", "peg_held_s", "obstacle_done",
               "obstacle_touched", "groove_done", "groove_share", "groove_max_side_force_n",
               "groove_left_at_xy_m", "egg_done", "egg_peak_g", "egg_in_band_s", "egg_broken", "tasks_done",
               "time_s", "status", "detail", "seconds"]


def write_csv(path: Path, grades: Sequence[ContestGrade]) -> None:
    """One row per submission: a column per task's evidence (booleans as 0/1), tasks done, the time
    (empty unless all four are done), how the run ended and what it took."""
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(CSV_COLUMNS)
        for g in grades:
            w.writerow([for_csv(g.path.name), g.result_word, *_task_cells(g.card), g.result.status,
                        for_csv(g.why), f"{g.result.wall_s:.2f}"])


def write_junit_tasks(path: Path, grades: Sequence[ContestGrade], suite: str) -> None:
    """A JUnit case per submission and task (``classname`` the submission, ``name`` the task): a task
    not done is a failure with its evidence; a run that did not build or run is an error in each."""
    cases = []
    for g in grades:
        share = g.result.wall_s / len(TASKS)
        lines = g.card.lines() if g.card is not None else []
        for k, task in enumerate(TASKS):
            classname = f"{suite}.{g.path.name}"
            if g.card is None:
                cases.append(Case(task, classname, share, "error", f"{g.result_word}: {g.why}", g.why))
                continue
            done = getattr(g.card, task).done
            cases.append(Case(task, classname, share, "pass" if done else "failure", lines[k].strip(),
                              "\n".join(lines)))
    write_junit(path, "crslab grade --contest", cases)


def summary_table(grades: Sequence[ContestGrade], stream: TextIO) -> None:
    """The leaderboard: rank, submission, result, time, and each task's mark."""
    ranked = sorted(grades, key=lambda g: g.ranking)
    names = [for_terminal(g.path.name) for g in ranked]
    name_w = max([len("submission")] + [len(n) for n in names])
    stream.write(f"rank  {'submission':<{name_w}}  {'result':<16}  {'time_s':>7}  "
                 + "  ".join(f"{t:<8}" for t in TASKS) + "\n")
    for rank, (name, g) in enumerate(zip(names, ranked), 1):
        time_s = "" if g.card is None or g.card.time_s is None else f"{g.card.time_s:7.2f}"
        marks = ["" if g.card is None else ("done" if getattr(g.card, t).done else "FAIL") for t in TASKS]
        stream.write(f"{rank:>4}  {name:<{name_w}}  {g.result_word:<16}  {time_s:>7}  "
                     + "  ".join(f"{m:<8}" for m in marks) + "\n")
    complete = sum(g.card is not None and g.card.done == 4 for g in grades)
    stream.write(f"{len(grades)} submissions: {complete} complete all four tasks\n")
