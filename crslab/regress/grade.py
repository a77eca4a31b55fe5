"""Grade a folder of lab files against a reference lab: every submission is built and run in a
process of its own (several at once), from a private copy of that one file, or of its student's
folder when the class came one folder per student (``alice/lab1.c``, as Gradescope and GitHub
Classroom export it: the folder's files are that student's submission, so a header of their own
beside the lab compiles; in the sandbox, it can read nothing else of the class folder), its
transcript compared with the reference's, and
the outcome classed as pass, mismatch, unmet (an expectation of the scenario failed), does not
compile, crashed, forbidden or hung. One broken
submission never stops the others: its process may crash, hang or be killed, and grading goes on.

Each status's grade class is attached to it (:class:`crslab.run.status.RunStatus`).
"""

from __future__ import annotations

import csv
import dataclasses
import os
import re
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol, TextIO

from crslab.executors.job import Executor
from crslab.executors.local import DEFAULT_TIMEOUT_S
from crslab.framework_facts import TICKS_PER_S
from crslab.lab.includes import with_own_headers
from crslab.regress.compare import DEFAULT_ABS_TOL, DEFAULT_REL_TOL, Comparison, compare
from crslab.regress.junit import Case, write_junit
from crslab.regress.transcript import split_lines
from crslab.run.board_run import DEFAULT_DEADLINE_S, NO_LIMITS, Limits
from crslab.run.budget import lab_cost
from crslab.run.status import ExitStatus, GradeClass, RunResult, RunStatus
from crslab.untrusted_text import for_csv, for_terminal
from crslab.worker.config import RunConfig

SHOWN_ALWAYS = (GradeClass.PASS, GradeClass.MISMATCH, GradeClass.DOES_NOT_COMPILE, GradeClass.CRASHED,
                GradeClass.HUNG)
"""The classes the summary always counts; any other (forbidden) is counted when it occurs."""
LAB_SUFFIXES = (".c", ".cpp")


MAX_FOLDER_FILES = 200
"""How many files of one student's folder are copied with their lab (a lab has a few headers)."""
MAX_FOLDER_BYTES = 16 * 1024 * 1024
"""How many bytes of one student's folder are copied in all."""
DEFINES_LAB = re.compile(rb"^[ \t]*(?:void[ \t]+)?lab[ \t]*\(", re.MULTILINE)


def _is_lab(path: Path) -> bool:
    return (path.is_file() or path.is_symlink()) and path.suffix.lower() in LAB_SUFFIXES


def _hidden(path: Path, folder: Path) -> bool:
    return any(part.startswith((".", "__")) for part in path.relative_to(folder).parts)


def folder_lab(student: Path) -> Path | None:
    """The lab file of one student's folder: its only lab file (``.c``, ``.cpp``, at any depth,
    hidden folders aside), else the first by name that defines ``lab(``, else the first by name;
    None when it holds none.

    >>> import tempfile
    >>> alice = Path(tempfile.mkdtemp())
    >>> _ = (alice / "util.c").write_text("int twice(int x) { return 2 * x; }\\n")
    >>> _ = (alice / "lab1.c").write_text("void lab(float a) { }\\n")
    >>> folder_lab(alice).name
    'lab1.c'
    """
    labs = sorted((p for p in student.rglob("*") if _is_lab(p) and not _hidden(p, student)),
                  key=lambda p: p.relative_to(student).as_posix())
    if len(labs) <= 1:
        return labs[0] if labs else None
    for lab in labs:
        try:
            if DEFINES_LAB.search(lab.read_bytes()[:4 * 1024 * 1024]):
                return lab
        except OSError:
            continue
    return labs[0]


@dataclass
class Found:
    """What a class folder holds: its submissions' lab files, in order, and for each one that came
    in a student's folder, that folder; the folders that hold no lab file."""

    labs: list[Path]
    folders: dict[Path, Path]
    empty: list[Path]

    def summary(self) -> str:
        """``N submissions: M files, K folders`` (and the folders without a lab file)."""
        files = len(self.labs) - len(self.folders)
        line = (f"{len(self.labs)} submission{'s' * (len(self.labs) != 1)}: {files} "
                f"file{'s' * (files != 1)}, {len(self.folders)} folder{'s' * (len(self.folders) != 1)}")
        if self.empty:
            names = ", ".join(for_terminal(p.name) + "/" for p in self.empty[:5])
            more = f" and {len(self.empty) - 5} more" if len(self.empty) > 5 else ""
            line += f"; no lab file in {names}{more}"
        return line


def find_submissions(folder: Path) -> list[Path]:
    """The submissions' lab files in ``folder``: each lab file (``.c``, ``.cpp``) directly in it,
    then each sub-folder's lab file (:func:`folder_lab`), by name."""
    return find_class(folder).labs


def find_class(folder: Path) -> Found:
    """Every submission of ``folder``: a lab file directly in it is graded alone; a sub-folder is
    one student's submission (``alice/lab1.c``; hidden folders aside), graded with its files."""
    entries = sorted(folder.iterdir())
    labs = [p for p in entries if _is_lab(p)]
    folders: dict[Path, Path] = {}
    empty = []
    for sub in entries:
        if not sub.is_dir() or sub.is_symlink() or sub.name.startswith((".", "__")):
            continue
        lab = folder_lab(sub)
        if lab is None:
            empty.append(sub)
        else:
            labs.append(lab)
            folders[lab] = sub
    return Found(labs, folders, empty)


def submission_name(lab: Path, student: Path | None) -> str:
    """How a report names a submission: its file's name, or ``alice/lab1.c`` for one in a folder."""
    return lab.name if student is None else f"{student.name}/{lab.relative_to(student).as_posix()}"


def read_folder(student: Path, lab: Path) -> tuple[tuple[str, bytes], ...]:
    """The files of one student's folder but its lab (which :func:`read_submission` reads), each by
    its path inside the folder: regular files, and links to files inside the folder, hidden
    folders aside. Raises ``PermissionError`` past :data:`MAX_FOLDER_FILES` or
    :data:`MAX_FOLDER_BYTES`."""
    root = student.resolve()
    files, total = [], 0
    for p in sorted(student.rglob("*")):
        if p == lab or _hidden(p, student):
            continue
        if p.is_symlink():
            if not p.resolve().is_relative_to(root):
                continue  # a link out of the student's folder is not theirs to hand in
        if not p.is_file():
            continue
        data = p.read_bytes()
        total += len(data)
        files.append((p.relative_to(student).as_posix(), data))
        if len(files) > MAX_FOLDER_FILES or total > MAX_FOLDER_BYTES:
            raise PermissionError(f"{student.name}/ holds more than {MAX_FOLDER_FILES} files or "
                                  f"{MAX_FOLDER_BYTES // 2**20} MB: too much for one submission")
    return tuple(files)


@dataclass
class Grade:
    """One submission's grade."""

    path: Path
    grade: GradeClass
    detail: str
    result: RunResult
    comparison: Comparison | None = None
    name: str = ""
    """How reports name it (``alice/lab1.c`` for a student's folder); empty: its file's name."""

    @property
    def label(self) -> str:
        """Its name in the reports."""
        return self.name or self.path.name

    @property
    def verdict(self) -> str:
        """``grade: detail`` in one line, the grade said once: a detail that already says it
        (``hang.c hung: lab() did not return ...``) stands alone.

        >>> r = RunResult(RunStatus.HUNG)
        >>> Grade(Path("hang.c"), GradeClass.HUNG, "hang.c hung: lab() did not return", r).verdict
        'hang.c hung: lab() did not return'
        >>> Grade(Path("c.c"), GradeClass.CRASHED, "c.c used a NULL pointer", r).verdict
        'crashed: c.c used a NULL pointer'
        """
        head = self.detail.partition(": ")[0]
        return self.detail if head == self.grade or head.endswith(f" {self.grade}") else \
            f"{self.grade}: {self.detail}"

    @property
    def exit_status(self) -> ExitStatus:
        """What ``crslab check`` exits with for this run against the reference: a run that reached
        its end gives 0 on a match and 1 on a mismatch, any other its own status's."""
        if self.result.status is RunStatus.OK:
            return ExitStatus.OK if self.grade == GradeClass.PASS else ExitStatus.MISMATCH
        return self.result.exit_status

    @property
    def report(self) -> str:
        """The full explanation: the failed expectations (one line each), the mismatch report, or
        the diagnostics."""
        r = self.result
        head = r.diagnosis() if r.failed_expectations else r.message
        if self.comparison is None:  # the run did not reach its end
            return "\n".join(x for x in (head, r.details) if x)
        parts = [head] if r.failed_expectations else []
        if not self.comparison.ok:
            parts.append(self.comparison.report(max_lines=10))
        return "\n".join(parts)


def _first_error(diagnostics: str, name: str) -> str:
    """The compiler's first ``error:`` line, naming the file rather than its full path."""
    for line in diagnostics.splitlines():
        if "error:" in line:
            head, _, rest = line.partition(name)
            return (name + rest) if rest else line.strip()
    return ""


def read_submission(path: Path) -> bytes:
    """The text of the one submission ``path``; a symbolic link is read as what it points to only
    when that is inside the submission's own folder. Raises ``PermissionError`` for a link out of
    it, ``OSError`` when it cannot be read."""
    if path.is_symlink():
        target = path.resolve()
        if not target.is_relative_to(path.parent.resolve()):
            raise PermissionError(f"{path.name} was stopped by the sandbox: it is a symbolic link to "
                                  f"{target}, outside the submissions folder")
    return path.read_bytes()


class Runner(Protocol):
    """How a built submission is run instead of to a fixed tick (``grade --contest``: as a contest
    run, :class:`crslab.regress.contest_grade.ContestRunner`): given its configuration (its build
    in it) and its text. Picklable: it travels with the job."""

    def __call__(self, config: RunConfig, text: str, deadline_s: float, limits: Limits) -> RunResult:
        ...


def run_one(path: Path, config: RunConfig, end_tick: int, deadline_s: float, limits: Limits,
            source: bytes | None = None, files: tuple[tuple[str, bytes], ...] = (),
            where: str = "", runner: Runner | None = None) -> RunResult:
    """Build the lab and run it on ``config``'s scenario with ``config``'s flags (in this process;
    the lab itself runs in a worker process of its own). ``wall_s`` counts the build too.
    ``source``: the submission's text, built from a private copy alone in a folder of its own,
    never the folder it came from; None builds ``path`` where it is (the trusted reference).
    ``files``: the rest of the student's folder (each by its path inside it), copied beside the
    lab, which goes at ``where`` inside it (default: its name). ``runner``: how to run it once built
    (None: to ``end_tick``)."""
    start = time.monotonic()
    if source is None:
        return _build_and_run(path, path, config, end_tick, deadline_s, limits, start, runner=runner)
    with tempfile.TemporaryDirectory(prefix="crslab-submission-") as folder:
        for name, data in files:
            copied = Path(folder) / name
            copied.parent.mkdir(parents=True, exist_ok=True)
            copied.write_bytes(data)
        copy = Path(folder) / (where or path.name)
        copy.parent.mkdir(parents=True, exist_ok=True)
        copy.write_bytes(source)
        return _build_and_run(path, copy, config, end_tick, deadline_s, limits, start, alone=not files,
                              root=Path(folder), runner=runner)


def _alone_note(path: Path, diagnostics: str) -> str:
    """When a lab graded alone includes a file that lies beside it in the class folder, why the
    compiler found no such file; else empty."""
    for m in re.finditer(r"'([^'\n]+)' file not found", diagnostics):
        if (path.parent / m.group(1)).is_file():
            return (f" ({m.group(1)} lies beside it, but a lab file directly in the class folder is "
                    "graded alone: give each student with files of their own a folder, "
                    f"{path.stem}/{path.name} and {path.stem}/{m.group(1)})")
    return ""


def _build_and_run(path: Path, source: Path, config: RunConfig, end_tick: int, deadline_s: float,
                   limits: Limits, start: float, alone: bool = False, root: Path | None = None,
                   runner: Runner | None = None) -> RunResult:
    from crslab.lab.build import LabBuildError, LabForbidden, build_lab
    from crslab.run.assemble import run_kept
    from crslab.run.board_run import RunError
    from crslab.scenario.load import ScenarioError, check_lab

    habits: tuple[str, ...] = ()  # the C89 habits it built with, once it built

    def ended(status: RunStatus, message: str, details: str = "") -> RunResult:
        return RunResult(status, message=message, details=details, lab_file=path,
                         wall_s=time.monotonic() - start, habits=habits)

    try:
        build = build_lab(source, native=config.build.native, sanitize=config.build.sanitized,
                          sandboxed=config.sandboxed)
    except LabForbidden as exc:
        return ended(RunStatus.FORBIDDEN, str(exc), exc.diagnostics)
    except LabBuildError as exc:
        first = _first_error(exc.diagnostics, path.name)
        note = _alone_note(path, exc.diagnostics) if alone else ""
        return ended(RunStatus.BUILD_ERROR, (first or str(exc)) + note, exc.diagnostics)
    # what the board's compiler would warn about, said in the report, by the file's path in the
    # submission (not the private copy's folder)
    inside = f"{root}{os.sep}" if root is not None else None
    habits = tuple(h.removeprefix(inside) if inside else h for h in build.habits)
    try:
        check_lab(config.scenario, build)
    except ScenarioError as exc:
        return ended(RunStatus.UNFIT, str(exc))
    try:
        built = dataclasses.replace(config, build=build)
        if runner is None:
            result = run_kept(built, end_tick, deadline_s=deadline_s, limits=limits)
        else:
            result = runner(built, with_own_headers(source, source.read_text(errors="replace")), deadline_s,
                            limits)
    except RunError as exc:
        return ended(exc.status, str(exc))
    return dataclasses.replace(result, lab_file=path, wall_s=time.monotonic() - start, habits=habits)


@dataclass(frozen=True)
class GradeJob:
    """One submission's run, as a job for an executor (:mod:`crslab.executors`): it carries the
    submission's text (``source``), so it runs anywhere, a Dask worker included."""

    path: Path
    config: RunConfig
    end_tick: int
    deadline_s: float
    limits: Limits
    source: bytes | None = None
    """The submission's text; None builds ``path`` in place (the reference, on this machine)."""
    files: tuple[tuple[str, bytes], ...] = ()
    """The rest of its student's folder, by path inside it (empty for a lab file graded alone)."""
    where: str = ""
    """The lab's path inside its student's folder (empty: its file's name)."""
    runner: Runner | None = None
    """How to run it once built (None: to ``end_tick``)."""

    @property
    def name(self) -> str:
        return self.path.name

    def run(self) -> RunResult:
        return run_one(self.path, self.config, self.end_tick, self.deadline_s, self.limits, self.source,
                       self.files, self.where, self.runner)

    def lost(self, status: RunStatus, message: str, elapsed_s: float = 0.0) -> RunResult:
        return RunResult(status, message=message, lab_file=self.path, wall_s=elapsed_s)


def run_many(paths: Sequence[Path], config: RunConfig, end_tick: int, *, jobs: int = 1,
             deadline_s: float = DEFAULT_DEADLINE_S, limits: Limits = NO_LIMITS,
             timeout_s: float = DEFAULT_TIMEOUT_S, private: bool = True,
             on_done: Callable[[RunResult], None] | None = None,
             executor: Executor | None = None,
             folders: dict[Path, Path] | None = None, runner: Runner | None = None) -> list[RunResult]:
    """Run every lab file in ``paths`` on ``executor`` (default: ``jobs`` local processes at a
    time); results in ``paths`` order, each naming its file (``lab_file``) and how long it took in
    all (``wall_s``). ``private``: each from a private copy of that one file's text (read here, so
    it runs anywhere; see :func:`run_one`), else built where it is (this machine only).
    ``folders``: for a lab that came in a student's folder, that folder (its files come too).
    ``runner``: how each is run once built (None: to ``end_tick``).

    A process that dies without answering counts as crashed; one that takes longer than
    ``timeout_s`` in all (building included) is killed and counts as hung, its ``wall_s`` the time
    it had run.
    """
    from crslab.executors.local import LocalExecutor

    executor = executor if executor is not None else LocalExecutor(jobs, timeout_s=timeout_s)
    results: dict[int, RunResult] = {}
    batch: list[tuple[int, GradeJob]] = []

    def done(index: int, result: RunResult) -> None:
        results[index] = result
        if on_done is not None:
            on_done(result)

    for i, path in enumerate(paths):
        source, files, where = None, (), ""
        student = (folders or {}).get(path)
        if private:
            try:
                source = read_submission(path)
                if student is not None:
                    files, where = read_folder(student, path), path.relative_to(student).as_posix()
            except PermissionError as exc:
                done(i, RunResult(RunStatus.FORBIDDEN, message=str(exc), lab_file=path))
                continue
            except OSError as exc:
                why = f"{path.name} cannot be read ({exc.strerror})"
                done(i, RunResult(RunStatus.BUILD_ERROR, message=why, lab_file=path))
                continue
        batch.append((i, GradeJob(path, config, end_tick, deadline_s, limits, source, files, where, runner)))
    executor.run([job for _, job in batch], lambda k, result: done(batch[k][0], result))
    return [results[i] for i in range(len(paths))]


def grade_result(result: RunResult, reference: RunResult, *, abs_tol: float = DEFAULT_ABS_TOL,
                 rel_tol: float = DEFAULT_REL_TOL) -> Grade:
    """Grade one submission's run against the reference's transcript. A run that reached its end
    with a failed expectation is ``unmet`` whatever its transcript; the detail names the first
    failure and says whether the transcript matched too."""
    path = result.lab_file or Path("?")
    if result.status not in (RunStatus.OK, RunStatus.UNMET):
        grade = result.status.graded(matched=False)
        return Grade(path, grade, result.message.splitlines()[0] if result.message else str(grade), result)
    comparison = compare(split_lines(reference.transcript, reference.calls),
                         split_lines(result.transcript, result.calls), abs_tol=abs_tol, rel_tol=rel_tol)
    grade = result.status.graded(matched=comparison.ok)
    if comparison.ok:
        detail = f"{comparison.got_count} lines match"
    else:
        first = comparison.diffs[0]
        when = f" ({first.got.time})" if first.got is not None and first.got.tick is not None else ""
        detail = f"{len(comparison.diffs)} lines differ; line {first.number}{when}: {first.reason}"
    if result.status is RunStatus.UNMET:
        failed = result.failed_expectations
        detail = (f"{len(failed)} of {len(result.expectations)} expectations failed; first at "
                  f"{failed[0].lines()[0]}; {detail}")
    return Grade(path, grade, detail, result, comparison)


def summary_table(grades: Sequence[Grade], stream: TextIO, *, width: int = 100) -> None:
    """The table a TA reads: one row per submission, then the counts."""
    names = [for_terminal(g.label) for g in grades]  # a file's name is the submitter's to choose
    name_w = max([len("submission")] + [len(n) for n in names])
    grade_w = max(len(c) for c in GradeClass)
    stream.write(f"{'submission':<{name_w}}  {'result':<{grade_w}}  detail\n")
    for name, g in zip(names, grades):
        detail = for_terminal(g.detail)
        detail = detail if len(detail) <= width else detail[:width - 3] + "..."
        stream.write(f"{name:<{name_w}}  {g.grade:<{grade_w}}  {detail}\n")
    stream.write(counts_line(grades) + "\n")


def counts_line(grades: Sequence[Grade]) -> str:
    """``N submissions: a pass, b mismatch, ...``."""
    shown = [c for c in GradeClass if c in SHOWN_ALWAYS or any(g.grade == c for g in grades)]
    counts = ", ".join(f"{sum(g.grade == c for g in grades)} {c}" for c in shown)
    return f"{len(grades)} submissions: {counts}"


def write_csv(path: Path, grades: Sequence[Grade]) -> None:
    """One row per submission: file, result, detail, lines, first differing line and its time, the
    seconds it took, how many of the scenario's expectations failed, how its run ended (``status``:
    ok, exited, nan, output-limit, ...), the exit status ``crslab check`` gives such a run, and
    how many lab() calls cost more than the budget (``--budget``) and that budget (instructions; a
    native run's in us)."""
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["submission", "result", "detail", "lines", "first_diff_line", "first_diff_t_s",
                    "seconds", "expectations_failed", "status", "exit_status", "over_budget", "budget"])
        for g in grades:
            lines = len(split_lines(g.result.transcript))
            first_line = first_t = ""
            if g.comparison is not None and g.comparison.diffs:
                d = g.comparison.diffs[0]
                first_line = str(d.number)
                if d.got is not None and d.got.tick is not None:
                    first_t = f"{d.got.tick / TICKS_PER_S:.3f}"
            cost = lab_cost(g.result.stats)
            w.writerow([for_csv(g.label), g.grade, for_csv(g.detail), lines, first_line, first_t,
                        f"{g.result.wall_s:.2f}", len(g.result.failed_expectations), g.result.status,
                        int(g.exit_status), cost["over_budget"], f"{cost['budget']:g}"])


def write_junit_grades(path: Path, grades: Sequence[Grade], suite: str) -> None:
    """A JUnit report: a mismatch or an unmet expectation is a failure (its text lists every
    failed expectation); does not compile, crashed, forbidden and hung are errors."""
    cases = []
    for g in grades:
        status = {GradeClass.PASS: "pass", GradeClass.MISMATCH: "failure",
                  GradeClass.UNMET: "failure"}.get(g.grade, "error")
        cases.append(Case(g.label, suite, g.result.wall_s, status, g.verdict, g.report))
    write_junit(path, "crslab grade", cases)


class Progress:
    """A progress bar on a terminal (one line per submission otherwise)."""

    def __init__(self, total: int, stream: TextIO | None = None) -> None:
        self.total, self.done = total, 0
        self.stream = stream if stream is not None else sys.stderr
        self.tty = self.stream.isatty()
        self.start = time.monotonic()

    def update(self, name: str, grade: str) -> None:
        """One more submission finished."""
        self.done += 1
        if self.tty:
            width = 30
            filled = width * self.done // max(1, self.total)
            elapsed = time.monotonic() - self.start
            self.stream.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total} "
                              f"{elapsed:5.1f} s  {for_terminal(name)[:30]:<30} {grade:<16}")
            if self.done == self.total:
                self.stream.write("\n")
        else:
            self.stream.write(f"[{self.done}/{self.total}] {for_terminal(name)}: {grade}\n")
        self.stream.flush()


def default_jobs() -> int:
    """Every core this process may use."""
    from crslab.executors.local import default_workers

    return default_workers()
