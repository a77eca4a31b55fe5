"""Grade a class by the contest's scorecard (``crslab grade DIR --contest``): every submission (a lab
file, or a student's folder: ``alice/final.c`` with its own headers) runs as a contest run
(:mod:`crslab.contest.run`: its own offsets, until its motion ends) in a process of its own, from
a private copy, in the sandbox, exactly as :mod:`crslab.regress.grade` runs a class, and is scored
by :func:`crslab.contest.scorecard.score`; no reference lab.

What a TA gets: a leaderboard ranked by tasks done, then by time (equal ones ranked equal);
``grades.csv`` with a column per task's evidence, the resting pose and a detail for every result;
``junit.xml`` with a case per submission and task; each submission's card (text and picture) and
transcript.
"""

from __future__ import annotations

import csv
import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO

from crslab.contest.offsets import Rest, contest_rest
from crslab.contest.run import contest_config, run_contest
from crslab.contest.scorecard import RunFacts, Scorecard, ScorecardError, score
from crslab.regress.junit import Case, write_junit
from crslab.run.board_run import Limits
from crslab.run.status import RunResult, RunStatus
from crslab.untrusted_text import for_csv, for_terminal
from crslab.worker.config import RunConfig

TASKS = Scorecard.TASKS


@dataclass(frozen=True)
class ContestRunner:
    """How ``grade --contest`` runs a built submission (a :class:`crslab.regress.grade.Runner`):
    resting where its own offsets say (or ``offsets``), as a contest run of ``duration_s`` (None:
    until its motion ends). Offsets that rest the arm in a fixture make it ``unfit``."""

    offsets: tuple[float, float] | None = None
    duration_s: float | None = None

    def rest(self, text: str) -> Rest:
        """Where the submission whose text is ``text`` rests."""
        return contest_rest(text, self.offsets)

    def __call__(self, config: RunConfig, text: str, deadline_s: float, limits: Limits) -> RunResult:
        from crslab.world import WorldError

        try:
            config = contest_config(config, self.rest(text))
        except WorldError as exc:
            return RunResult(RunStatus.UNFIT, message=f"{config.build.source.name}: {exc}")
        return run_contest(config, duration_s=self.duration_s, deadline_s=deadline_s, limits=limits)


@dataclass(frozen=True)
class ContestGrade:
    """One submission's run and its card (None when it did not run to a log: then ``why``)."""

    path: Path
    result: RunResult
    card: Scorecard | None
    why: str = ""
    name: str = ""
    """How reports name it (``alice/final.c`` for a student's folder); empty: its file's name."""
    rest: Rest | None = None

    @property
    def label(self) -> str:
        """Its name in the reports."""
        return self.name or self.path.name

    @property
    def result_word(self) -> str:
        """``complete`` (all four tasks), ``N of 4``, or how the run failed (``does not compile``, ...;
        ``unfit``: its offsets rest the arm in a fixture, the detail says which)."""
        if self.card is None:
            if self.result.status in (RunStatus.OK, RunStatus.UNFIT):  # no reference to mismatch here
                return "no log" if self.result.status is RunStatus.OK else "unfit"
            return str(self.result.status.graded(matched=False))
        return "complete" if self.card.complete else f"{self.card.done} of 4"

    @property
    def ranking(self) -> tuple[int, float]:
        """What ranks it: more tasks done first, then the shorter time (to the millisecond, the
        log's resolution); equal keys rank equal."""
        done = self.card.done if self.card is not None else -1
        time_s = self.card.time_s if self.card is not None and self.card.time_s is not None else float("inf")
        return (-done, round(time_s, 3))

    @property
    def detail(self) -> str:
        """One line: how the run went and, for each task not done, its card line."""
        if self.card is None:
            return self.why
        lines = self.card.lines()
        if self.card.complete:
            text = f"all four tasks in {self.card.time_s:.2f} s"
        else:
            text = "; ".join(" ".join(line.split()) for line, task in zip(lines, TASKS)
                             if not getattr(self.card, task).done)
        if self.why:
            text = f"{self.why}; {text}"
        return text


def grade_contest(result: RunResult, world: Any, config: RunConfig, rest: Rest | None,
                  name: str = "") -> ContestGrade:
    """Score one submission's run (its scope log) in ``world``; the grade keeps no log."""
    path = result.lab_file or Path("?")
    slim = dataclasses.replace(result, log=None)
    why = (result.message or str(result.status)).splitlines()[0] if result.status is not RunStatus.OK else ""
    if not result.log:
        return ContestGrade(path, slim, None, why or "the run kept no scope log", name, rest)
    facts = RunFacts(result.status, why, result.end_tick, result.stats, rest, config.startup_ticks,
                     config.budget_instructions)
    try:
        card = score(result.log, world, facts)
    except ScorecardError as exc:
        return ContestGrade(path, slim, None, str(exc), name, rest)
    return ContestGrade(path, slim, card, why, name, rest)


def ranks(grades: Sequence[ContestGrade]) -> list[tuple[int, ContestGrade]]:
    """The leaderboard: each grade with its rank, best first; equal keys share a rank (1, 1, 3).

    >>> from crslab.run.status import RunResult, RunStatus
    >>> g = [ContestGrade(Path(n), RunResult(RunStatus.OK), None) for n in "ba"]
    >>> [(r, x.label) for r, x in ranks(g)]
    [(1, 'a'), (1, 'b')]
    """
    ordered = sorted(grades, key=lambda g: (g.ranking, g.label))
    out, rank = [], 0
    for i, g in enumerate(ordered):
        if i == 0 or g.ranking != ordered[i - 1].ranking:
            rank = i + 1
        out.append((rank, g))
    return out


CSV_COLUMNS = ["submission", "rank", "result", "peg_done", "peg_depth_m", "peg_held_s", "obstacle_done",
               "obstacle_touched_by", "obstacle_passed", "groove_done", "groove_share",
               "groove_max_side_force_n", "groove_left_at_xy_m", "egg_done", "egg_peak_g", "egg_in_band_s",
               "egg_broken_by", "tasks_done", "time_s", "rest_motor2_rad", "rest_motor3_rad", "rest_from",
               "run_end_s", "status", "detail", "seconds"]


def _task_cells(card: Scorecard | None) -> list[str]:
    if card is None:
        return [""] * 16
    d = card.as_dict()["tasks"]
    p, o, g, e = d["peg"], d["obstacle"], d["groove"], d["egg"]
    left = "" if g["left_at"] is None else f"{g['left_at'][0]:.4f} {g['left_at'][1]:.4f}"
    touched_by = " ".join(x.replace(" ", "_") for x in o["touched_by"])
    cells = [p["done"], p["depth_m"], p["held_s"], o["done"], touched_by, o["passed"] or "", g["done"],
             g["share"], g["max_side_force_n"], left, e["done"], e["peak_g"], e["in_band_s"],
             (e["broken_by"] or "").replace(" ", "_"), card.done,
             "" if card.time_s is None else f"{card.time_s:.3f}"]
    return [str(int(c)) if isinstance(c, bool) else str(c) for c in cells]


def write_csv(path: Path, grades: Sequence[ContestGrade]) -> None:
    """One row per submission, in rank order: a column per task's evidence (booleans as 0/1;
    several words joined by ``_``), tasks done, the time (empty unless all four are done), the
    resting pose and where it came from, when the run ended, how, a detail, the seconds it took."""
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(CSV_COLUMNS)
        for rank, g in ranks(grades):
            rest = ["", "", ""] if g.rest is None else \
                [f"{g.rest.motor_rad[1]:.6f}", f"{g.rest.motor_rad[2]:.6f}", g.rest.source]
            end = "" if g.card is None else f"{g.card.ended.end_s:.3f}"
            w.writerow([for_csv(g.label), rank, g.result_word, *_task_cells(g.card), *rest, end,
                        g.result.status, for_csv(g.detail), f"{g.result.wall_s:.2f}"])


def write_junit_tasks(path: Path, grades: Sequence[ContestGrade], suite: str) -> None:
    """A JUnit case per submission and task (``classname`` the submission, ``name`` the task): a task
    not done is a failure with its evidence; a run that did not build or run is an error in each."""
    cases = []
    for g in grades:
        share = g.result.wall_s / len(TASKS)
        lines = g.card.lines() if g.card is not None else []
        for k, task in enumerate(TASKS):
            classname = f"{suite}.{g.label}"
            if g.card is None:
                cases.append(Case(task, classname, share, "error", f"{g.result_word}: {g.why}", g.why))
                continue
            done = getattr(g.card, task).done
            cases.append(Case(task, classname, share, "pass" if done else "failure", lines[k].strip(),
                              "\n".join(lines)))
    write_junit(path, "crslab grade --contest", cases)


def summary_table(grades: Sequence[ContestGrade], stream: TextIO) -> None:
    """The leaderboard: rank, submission, result, time, and each task's mark."""
    ranked = ranks(grades)
    names = [for_terminal(g.label) for _, g in ranked]
    name_w = max([len("submission")] + [len(n) for n in names])
    stream.write(f"rank  {'submission':<{name_w}}  {'result':<16}  {'time_s':>7}  "
                 + "  ".join(f"{t:<8}" for t in TASKS) + "\n")
    for (rank, g), name in zip(ranked, names):
        time_s = "" if g.card is None or g.card.time_s is None else f"{g.card.time_s:7.2f}"
        marks = ["" if g.card is None else ("done" if getattr(g.card, t).done else "FAIL") for t in TASKS]
        stream.write(f"{rank:>4}  {name:<{name_w}}  {g.result_word:<16}  {time_s:>7}  "
                     + "  ".join(f"{m:<8}" for m in marks) + "\n")
    complete = sum(g.card is not None and g.card.complete for g in grades)
    stream.write(f"{len(grades)} submissions: {complete} complete all four tasks\n")
