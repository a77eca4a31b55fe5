"""``crslab record``, ``crslab check`` and ``crslab grade``: golden transcripts and regression.

Exit statuses: 0 match (every submission passes), 1 mismatch or a failed scenario expectation,
2 bad input; ``record`` and ``check`` give ``crslab sim``'s statuses when the lab itself crashes
(3), hangs (4), ...
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING

from crslab.cli import CliError
from crslab.cli.autograder_report import add_report_options, run_report
from crslab.cli.contest_commands import DURATION_DEFAULT, OFFSETS_DEFAULT
from crslab.cli.executor_options import add_executor_options, executor_from_args
from crslab.cli.run_options import (
    add_c28x_option,
    add_run_options,
    config_from_args,
    limits_from_args,
    run_to_end,
)
from crslab.cli.run_report import notices
from crslab.contest.offsets import Rest
from crslab.contest.run import CONTEST_SCENARIO, CONTEST_WORLD
from crslab.executors.job import Executor
from crslab.framework_facts import TICKS_PER_S
from crslab.lab.c28x_check import C28xReport, check_lab
from crslab.lab.compile_process import LabBuildError
from crslab.lab.includes import with_own_headers
from crslab.output_paths import folder as made_folder
from crslab.regress.compare import DEFAULT_ABS_TOL, DEFAULT_REL_TOL, compare
from crslab.regress.junit import Case, write_junit
from crslab.regress.runner import plant_fields, run_header
from crslab.regress.transcript import (
    GoldenError,
    read_golden,
    recorded_run,
    sha256_of,
    split_lines,
    write_golden,
)
from crslab.run.api import DEFAULT_REST_MOTOR_RAD
from crslab.run.budget import budget_line
from crslab.run.status import ExitStatus, GradeClass, RunResult, RunStatus
from crslab.scenario.event import seconds_to_tick
from crslab.untrusted_text import for_terminal, for_text
from crslab.worker.config import RunConfig

if TYPE_CHECKING:
    from crslab.regress.grade import Found


def non_negative(text: str) -> float:
    """argparse type: a number >= 0."""
    value = float(text)
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text}")
    return value


def add_tolerance_options(p: argparse.ArgumentParser) -> None:
    """--abs-tol and --rel-tol."""
    p.add_argument("--abs-tol", type=non_negative, default=DEFAULT_ABS_TOL, metavar="X",
                   help="numbers match when they differ by at most this (default: %(default)g, one unit "
                   "in the last digit of %%.2f)")
    p.add_argument("--rel-tol", type=non_negative, default=DEFAULT_REL_TOL, metavar="X",
                   help="... or by at most this fraction of the larger (default: %(default)g)")


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``record``, ``check`` and ``grade`` subcommands."""
    p = sub.add_parser("record", help="run a lab on a scenario and save its transcript as a golden file",
                       description="Run a lab file on a scenario as fast as possible and write what it "
                       "printed, exactly, after a small header naming the lab (and its hash), the "
                       "scenario and crslab's version. Nothing is written when the run does not end "
                       "normally or an expectation of the scenario fails.")
    add_run_options(p)
    p.add_argument("-o", "--output", type=Path, required=True, metavar="FILE",
                   help="the golden file to write")
    p.set_defaults(func=run_record)

    p = sub.add_parser("check", help="run a lab and compare what it prints with a golden file",
                       description="Run a lab file and compare its transcript with a golden file, line by "
                       "line: numbers match within the tolerances, all other text exactly. The scenario, "
                       "duration, resting pose, startup delay, motor board and plant file default to the "
                       "golden file's. Exit 0 on a match, 1 on a mismatch or a failed scenario expectation, "
                       "2 on bad input.")
    add_run_options(p)
    p.add_argument("--golden", type=Path, required=True, metavar="FILE",
                   help="the golden file (from 'crslab record', or a transcript from 'crslab sim')")
    add_tolerance_options(p)
    p.add_argument("-o", "--junit", type=Path, metavar="FILE", help="also write a JUnit XML report")
    p.add_argument("--max-report", type=int, default=5, metavar="N",
                   help="differing lines to show (default: %(default)s)")
    p.set_defaults(func=run_check)

    p = sub.add_parser("grade", help="grade a folder of lab files against a reference lab",
                       description="Run every submission in a folder on a scenario: each lab file (.c, "
                       ".cpp) directly in it, graded alone, and each sub-folder as one student's "
                       "submission (alice/lab1.c, as Gradescope and GitHub Classroom export a class: "
                       "the folder's files come with its lab, so a header of the student's own "
                       "compiles), each in a process of its own and several at once, each compiled "
                       "and run in the sandbox from a private copy, compare each transcript with the "
                       "reference lab's, and class each as pass, mismatch, unmet (an expectation of the "
                       "scenario failed), does not compile, crashed, forbidden (the sandbox stopped it) "
                       "or hung. Writes a summary table (stdout and "
                       "summary.txt), grades.csv, "
                       "junit.xml, and every transcript and report, into --out. With --contest instead of "
                       "a reference: score each by the final project's contest (docs/contest.md).")
    p.add_argument("submissions", type=Path, metavar="SUBMISSIONS_DIR",
                   help="folder of lab files, or of one folder per student")
    against = p.add_mutually_exclusive_group(required=True)
    against.add_argument("--reference", type=Path, metavar="FILE",
                         help="the reference lab file (or --contest)")
    against.add_argument("--contest", action="store_true",
                         help="grade by the final project's scorecard instead of a reference "
                         "(docs/contest.md): each submission runs as 'crslab contest' runs it; grades.csv "
                         "has a column per task's evidence, its rank, its resting pose and a detail, "
                         "junit.xml a case per submission and task, cards/ each card (text and picture). "
                         "--contest changes these "
                         f"defaults: --world {CONTEST_WORLD} (not none), --scenario {CONTEST_SCENARIO} (not "
                         "tour), --duration until each arm comes to rest (not the scenario's end), --offsets "
                         "each lab's own offset_Enc2_rad and offset_Enc3_rad (not crslab's arm's)")
    add_run_options(p)
    for action in p._actions:  # the reference is the lab here
        if action.dest == "lab":
            action.help = argparse.SUPPRESS
        elif action.dest == "world":
            action.help += f"; with --contest: default {CONTEST_WORLD}"
        elif action.dest == "scenario":
            action.help += f"; with --contest: default {CONTEST_SCENARIO}"
        elif action.dest == "duration":
            action.help += f"; with --contest: default {DURATION_DEFAULT}"
        elif action.dest == "offsets":
            action.help += f"; with --contest: default {OFFSETS_DEFAULT}"
    add_tolerance_options(p)
    p.add_argument("-o", "--out", type=Path, default=Path("crslab-grade"), metavar="DIR",
                   help="where the reports go (default: %(default)s)")
    add_executor_options(p, "submission")
    add_report_options(p)
    add_c28x_option(p)
    # grading runs many untrusted labs at once: bound each one's memory and CPU by default
    p.set_defaults(func=run_grade, mem_limit_mb=GRADE_MEM_LIMIT_MB, cpu_limit=GRADE_CPU_LIMIT_S)
    for action in p._actions:
        if action.dest == "mem_limit_mb":
            action.help = f"memory limit of each lab's process (default for grade: {GRADE_MEM_LIMIT_MB})"
        elif action.dest == "cpu_limit":
            action.help = f"CPU-time limit of each lab's process (default for grade: {GRADE_CPU_LIMIT_S:g} s)"


GRADE_MEM_LIMIT_MB = 2048
GRADE_CPU_LIMIT_S = 120.0


def _end_tick(args: argparse.Namespace, config: RunConfig) -> int:
    return seconds_to_tick(args.duration) if args.duration else config.scenario.end_tick


def _run(config: RunConfig, args: argparse.Namespace, end_tick: int) -> RunResult:
    result = run_to_end(config, end_tick, args)
    for line in notices(config.build.source.name, result.stats, config.build.generation, config.build.source):
        print(f"crslab {args.command}: {line}", file=sys.stderr)
    return result


def _say_budget(args: argparse.Namespace, result: RunResult) -> None:
    """What ``--budget`` counted: lab()'s calls, their cost, those over the budget."""
    cost = budget_line(result.stats)
    if cost is not None:
        print(f"crslab {args.command}: {cost}", file=sys.stderr)


def run_record(args: argparse.Namespace) -> int:
    """``crslab record``."""
    config = config_from_args(args)
    end_tick = _end_tick(args, config)
    result = _run(config, args, end_tick)
    if not result.ok:
        for expectation in result.failed_expectations:
            for line in expectation.lines():
                print(f"crslab record: expectation failed: {line}", file=sys.stderr)
        print(f"crslab record: {for_terminal(result.message or result.status)}; nothing was written",
              file=sys.stderr)
        return result.exit_status
    try:
        write_golden(args.output, run_header(config, end_tick, args.scenario, args.plant, args.world),
                     result.transcript)
    except OSError as exc:
        raise CliError(f"{args.output}: cannot write the golden file ({exc.strerror})") from None
    lines = len(split_lines(result.transcript))
    print(f"crslab record: {lines} lines ({end_tick / TICKS_PER_S:.3f} s simulated) written to {args.output}",
          file=sys.stderr)
    _say_budget(args, result)
    return ExitStatus.OK


def run_check(args: argparse.Namespace) -> int:
    """``crslab check``."""
    try:
        golden = read_golden(args.golden)
    except GoldenError as exc:
        raise CliError(str(exc)) from None
    if args.max_report < 1:
        raise CliError(f"--max-report must be at least 1, got {args.max_report}")
    header = golden.header
    chosen = args.scenario
    try:  # the options left out are the golden file's (one reading, shared with the pytest fixture)
        run = recorded_run(golden, [Path.cwd()]).overridden(
            scenario=args.scenario, duration_s=args.duration,
            rest_motor_rad=(DEFAULT_REST_MOTOR_RAD[0], *args.offsets) if args.offsets else None,
            startup_delay=False if args.no_startup_delay else None, motor_board=args.motor_board,
            plant=str(args.plant) if args.plant else None, world=args.world)
    except GoldenError as exc:
        raise CliError(str(exc)) from None
    args.scenario, args.duration = run.scenario, run.duration_s
    args.no_startup_delay = run.startup_delay is False
    args.motor_board = run.motor_board
    args.plant = Path(run.plant) if run.plant else None
    args.world = run.world
    config = config_from_args(args, rest_motor_rad=run.rest_motor_rad)
    recorded = header.get("scenario_sha256")
    if chosen is not None and header.get("scenario") not in (None, chosen):
        print(f"crslab check: note: {args.golden} was recorded on scenario {header['scenario']}, "
              f"not {chosen}", file=sys.stderr)
    elif recorded and recorded != sha256_of(Path(config.scenario.source).read_bytes()):
        print(f"crslab check: note: scenario {config.scenario.name} has changed since {args.golden} was "
              "recorded", file=sys.stderr)
    plant_recorded = header.get("plant_sha256")
    if args.plant and plant_recorded and plant_recorded != plant_fields(args.plant).get("plant_sha256"):
        print(f"crslab check: note: plant file {args.plant} differs from the one {args.golden} was recorded "
              "with", file=sys.stderr)
    end_tick = _end_tick(args, config)
    start = time.monotonic()
    result = _run(config, args, end_tick)
    _say_budget(args, result)
    comparison = compare(split_lines(golden.body), split_lines(result.transcript, result.calls),
                         abs_tol=args.abs_tol, rel_tol=args.rel_tol)
    report = comparison.report(max_lines=args.max_report)
    if not result.ok:
        report = f"{result.diagnosis()}\n{report}"
    report = for_text(report)  # it quotes what the lab printed
    print(report)
    status = result.exit_status if not result.ok else (
        ExitStatus.OK if comparison.ok else ExitStatus.MISMATCH)
    if args.junit:
        name = f"{config.build.source.name} on {config.scenario.name}"
        outcome = {ExitStatus.OK: "pass", ExitStatus.MISMATCH: "failure"}.get(status, "error")
        message = report.splitlines()[0]
        try:
            write_junit(args.junit, "crslab check", [Case(name, "crslab.check", time.monotonic() - start,
                                                          outcome, message, report)])
        except OSError as exc:
            raise CliError(f"{args.junit}: cannot write the JUnit report ({exc.strerror})") from None
    return status


def run_grade(args: argparse.Namespace) -> int:
    """``crslab grade``."""
    from crslab.regress import grade as g

    if args.report:
        return run_report(args)
    if args.contest:
        return run_grade_contest(args)
    folder: Path = args.submissions
    if not folder.is_dir():
        raise CliError(f"{folder}: no such folder of submissions")
    if args.jobs is not None and args.jobs < 1:
        raise CliError(f"--jobs must be at least 1, got {args.jobs}")
    args.lab = args.reference
    config = config_from_args(args)
    end_tick = _end_tick(args, config)
    limits = limits_from_args(args)
    reference_path = args.reference.resolve()
    found = g.find_class(folder)
    found.labs = [p for p in found.labs if p.resolve() != reference_path]
    subs = found.labs
    if not subs:
        raise CliError(f"{folder}: no lab files (.c, .cpp) to grade, directly in it or in a folder per "
                       "student")
    try:
        for sub_dir in ("transcripts", "reports"):
            made_folder(args.out / sub_dir)
    except OSError as exc:
        raise CliError(f"{args.out}: cannot write the reports there ({exc.strerror})") from None

    executor = executor_from_args(args)  # first: an unreachable scheduler is said at once
    try:
        [reference] = g.run_many([args.reference], config, end_tick, jobs=1, deadline_s=args.deadline,
                                 limits=limits, timeout_s=args.timeout, private=False)
        if reference.status is RunStatus.UNMET:
            first = reference.failed_expectations[0].lines()[0]
            raise CliError(f"the reference lab {args.reference.name} does not meet the scenario's "
                           f"expectations: {reference.message}; the first: {first}")
        if not reference.ok:
            raise CliError(f"the reference lab did not run: {reference.message or reference.status}")
        grades = _grade_all(args, found, config, end_tick, reference, executor)
    finally:
        executor.close()
    return _write_grades(args, subs, grades, reference, config)


def _grade_all(args: argparse.Namespace, found: Found, config: RunConfig, end_tick: int,
               reference: RunResult, executor: Executor) -> dict:
    """Run and grade every submission on ``executor``; their grades by path."""
    from crslab.regress import grade as g

    subs = found.labs
    print(f"crslab grade: {found.summary()}", file=sys.stderr)
    print(f"crslab grade: {len(subs)} submissions against {args.reference.name} on {config.scenario.name} "
          f"({end_tick / TICKS_PER_S:.3f} s), {executor.description}", file=sys.stderr)

    progress = g.Progress(len(subs))
    grades: dict[Path, g.Grade] = {}

    def on_done(result: RunResult) -> None:
        grade = g.grade_result(result, reference, abs_tol=args.abs_tol, rel_tol=args.rel_tol)
        grade.name = g.submission_name(grade.path, found.folders.get(grade.path))
        grades[grade.path] = grade
        progress.update(grade.label, grade.grade)

    g.run_many(subs, config, end_tick, deadline_s=args.deadline, limits=limits_from_args(args),
               on_done=on_done, executor=executor, folders=found.folders)
    return grades


def _write_grades(args: argparse.Namespace, subs: list[Path], grades: dict, reference: RunResult,
                  config: RunConfig) -> int:
    """Write the reports into ``--out`` and the summary on stdout; the exit status."""
    from crslab.regress import grade as g

    ordered = [grades[p] for p in subs]
    out = args.out
    c28x = {} if args.no_c28x_check else c28x_reports(subs, sandboxed=not args.no_sandbox,
                                                      jobs=args.jobs or os.cpu_count() or 1)
    (out / "transcripts" / f"{args.reference.name}.reference.txt").write_bytes(reference.transcript)
    for grade in ordered:
        transcript = out / "transcripts" / f"{grade.label}.txt"
        report = out / "reports" / f"{grade.label}.txt"
        for made in (transcript.parent, report.parent):  # alice/lab1.c.txt for a student's folder
            made.mkdir(parents=True, exist_ok=True)
        transcript.write_bytes(grade.result.transcript)
        # the C89 habits it built with, one line each as crslab sim says them, then the C28x check's
        board = [f"warning: {line}" for line in grade.result.habits]
        board += c28x.get(grade.path, C28xReport()).lines()
        extra = "\n" + "\n".join(board) + "\n" if board else ""
        if grade.grade != GradeClass.PASS:
            more = "" if grade.report.strip() == grade.detail else f"\n{grade.report}\n"  # not said twice
            report.write_text(for_text(f"{grade.verdict}\n{more}{extra}"))
        elif board:
            report.write_text(for_text(f"{grade.grade}{extra}"))
    g.write_csv(out / "grades.csv", ordered)
    g.write_junit_grades(out / "junit.xml", ordered, f"crslab.grade.{config.scenario.name}")
    with (out / "summary.txt").open("w") as f:
        g.summary_table(ordered, f)
    g.summary_table(ordered, sys.stdout)
    habits = sum(1 for x in ordered if x.result.habits)
    if habits:
        print(f"crslab grade: {habits} of {len(subs)} submissions use C89 habits that newer compilers refuse "
              "(the board's compiler warns and builds them, so does crslab): in their reports",
              file=sys.stderr)
    differ = sum(1 for r in c28x.values() if r.findings)
    if differ:
        print(f"crslab grade: {differ} of {len(subs)} submissions have places where the C28x's widths change "
              "a result (int 16 bits, double 32), on the board as in crslab's runs: in their reports",
              file=sys.stderr)
    print(f"crslab grade: reports in {out}/ (summary.txt, grades.csv, junit.xml, transcripts/, reports/)",
          file=sys.stderr)
    return ExitStatus.OK if all(x.grade == GradeClass.PASS for x in ordered) else ExitStatus.MISMATCH


def c28x_reports(subs: list[Path], *, sandboxed: bool, jobs: int) -> dict[Path, C28xReport]:
    """The C28x arithmetic check of every submission, a few at a time (each is two compiles), each
    from its text alone, as grade builds it: never from the class folder, where the others are."""
    from concurrent.futures import ThreadPoolExecutor

    from crslab.regress.grade import read_submission

    def one(path: Path) -> C28xReport:
        try:
            text = read_submission(path)
        except (OSError, LabBuildError) as exc:
            return C28xReport(skipped=str(exc))
        return check_lab(path, sandboxed=sandboxed, text=text, alone=True)

    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        reports = pool.map(one, subs)
        return dict(zip(subs, reports))


def run_grade_contest(args: argparse.Namespace) -> int:
    """``crslab grade DIR --contest``: every submission run as a contest run and scored by its card."""
    from crslab.regress import contest_grade as cg
    from crslab.regress import grade as g

    folder: Path = args.submissions
    if not folder.is_dir():
        raise CliError(f"{folder}: no such folder of submissions")
    if args.jobs is not None and args.jobs < 1:
        raise CliError(f"--jobs must be at least 1, got {args.jobs}")
    args.world = args.world or CONTEST_WORLD
    args.scenario = args.scenario or CONTEST_SCENARIO
    args.lab = None   # the configuration is built once with crslab's own lab; each submission is rebuilt
    config = config_from_args(args, log=True)   # the world read once: every run takes it as it is
    world = config.world
    if world.is_free_air:
        raise CliError(f"{args.world}: world {world.name!r} has no fixtures: the contest needs the hole, the "
                       "obstacle, the groove and the egg (the contest world has them)")
    found = g.find_class(folder)
    subs = found.labs
    if not subs:
        raise CliError(f"{folder}: no lab files (.c, .cpp) to grade, directly in it or in a folder per "
                       "student")
    out = args.out
    try:
        for sub_dir in ("cards", "transcripts"):
            made_folder(out / sub_dir)
    except OSError as exc:
        raise CliError(f"{out}: cannot write the reports there ({exc.strerror})") from None
    runner = cg.ContestRunner(tuple(args.offsets) if args.offsets else None, args.duration)
    executor = executor_from_args(args)
    long = f"{args.duration:g} s" if args.duration else "until each arm comes to rest"
    print(f"crslab grade: {found.summary()}", file=sys.stderr)
    print(f"crslab grade: {len(subs)} submissions in the {world.source} world on {config.scenario.name} "
          f"({long}, each resting where its own offsets say), by the contest's scorecard, "
          f"{executor.description}", file=sys.stderr)
    progress = g.Progress(len(subs))
    grades: dict[Path, cg.ContestGrade] = {}

    def on_done(result: RunResult) -> None:
        path = result.lab_file or Path("?")
        name = g.submission_name(path, found.folders.get(path))
        try:
            text = g.read_submission(path).decode("utf-8", "replace")
            if found.folders.get(path) is not None:  # a student's folder: her own headers are in her build
                text = with_own_headers(path, text)
            rest: Rest | None = runner.rest(text)
        except OSError:
            rest = None
        grade = cg.grade_contest(result, world, config, rest, name)
        write_contest_files(out, grade, result, world)
        grades[path] = grade
        progress.update(grade.label, grade.result_word)

    try:
        g.run_many(subs, config, 0, deadline_s=args.deadline, limits=limits_from_args(args), on_done=on_done,
                   executor=executor, folders=found.folders, runner=runner)
    finally:
        executor.close()
    ordered = [grades[p] for p in subs]
    cg.write_csv(out / "grades.csv", ordered)
    cg.write_junit_tasks(out / "junit.xml", ordered, "crslab.contest")
    with (out / "summary.txt").open("w") as f:
        cg.summary_table(ordered, f)
    cg.summary_table(ordered, sys.stdout)
    print(f"crslab grade: reports in {out}/ (summary.txt, grades.csv, junit.xml, cards/, transcripts/)",
          file=sys.stderr)
    complete = all(x.card is not None and x.card.complete for x in ordered)
    return ExitStatus.OK if complete else ExitStatus.MISMATCH


def write_contest_files(out: Path, grade: object, result: RunResult, world: object) -> None:
    """One submission's card (``cards/NAME.txt``, and ``cards/NAME.png`` when it ran), its
    transcript (``transcripts/NAME.txt``), named as the reports name it (``alice/final.c``)."""
    from crslab.regress.contest_grade import ContestGrade

    assert isinstance(grade, ContestGrade)
    card_text = out / "cards" / f"{grade.label}.txt"
    transcript = out / "transcripts" / f"{grade.label}.txt"
    for made in (card_text.parent, transcript.parent):
        made.mkdir(parents=True, exist_ok=True)
    transcript.write_bytes(result.transcript)
    if grade.card is None:
        details = f"\n{result.details}\n" if result.details else "\n"
        card_text.write_text(for_text(f"{grade.result_word}: {grade.why}{details}"))
        return
    card_text.write_text(for_text("\n".join(grade.card.lines()) + "\n"))
    from crslab.contest.card_plot import draw_card

    assert result.log is not None
    draw_card(result.log, world, grade.card, card_text.with_suffix(".png"))
