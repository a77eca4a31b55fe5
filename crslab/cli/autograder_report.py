"""``crslab grade SUBMISSION --report gradescope|prairielearn FILE``: one submission graded on
each test (a scenario with points) and the platform's results file written (docs/autograder.md).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from crslab.cli import CliError
from crslab.cli.executor_options import executor_from_args
from crslab.cli.run_options import config_from_args, limits_from_args
from crslab.regress import autograder as ag
from crslab.regress import grade as g
from crslab.run.status import ExitStatus
from crslab.scenario.event import seconds_to_tick
from crslab.scenario.load import DEFAULT_SCENARIO
from crslab.untrusted_text import for_terminal


def add_report_options(p: argparse.ArgumentParser) -> None:
    """``--report``, ``--tests`` and ``--points``."""
    p.add_argument(
        "--report",
        nargs=2,
        metavar=("PLATFORM", "FILE"),
        help="grade the one submission in SUBMISSIONS_DIR for an autograder platform and write its "
        f"results file: {' or '.join(ag.PLATFORMS)} (e.g. --report gradescope "
        "/autograder/results/results.json)",
    )
    p.add_argument(
        "--tests",
        type=Path,
        metavar="FILE",
        help="with --report: a TOML file of [[test]] tables (scenario, points, optional name and "
        "duration); default: one test, --scenario, worth --points",
    )
    p.add_argument(
        "--points",
        type=float,
        default=1.0,
        metavar="P",
        help="with --report and no --tests: the points of the one test (default: %(default)g)",
    )


def run_report(args: argparse.Namespace) -> int:
    """Grade one submission on each test and write the platform's results file."""
    platform, out = args.report[0], Path(args.report[1])
    if platform not in ag.PLATFORMS:
        raise CliError(f"--report {platform}: no such platform; choose one of {', '.join(ag.PLATFORMS)}")
    tests = _tests(args)
    folder: Path = args.submissions
    if folder.is_file():
        found = [folder]
    elif folder.is_dir():
        reference = args.reference.resolve()
        found = [p for p in g.find_submissions(folder) if p.resolve() != reference]
    else:
        raise CliError(f"{folder}: no such submission file or folder")
    if len(found) != 1:
        ag.write_results(out, ag.not_one_submission(platform, found, folder))
        print(
            f"crslab grade: {folder}: expected exactly one lab file, found {len(found)}; "
            f"{out} gives no points",
            file=sys.stderr,
        )
        return ExitStatus.MISMATCH
    [submission] = found
    # the submission folder is the student's: a header beside the lab comes with it
    folders = {submission: submission.parent} if folder.is_dir() else {}
    executor = executor_from_args(args)
    start = time.monotonic()
    results = []
    try:
        for test in tests:
            args.lab, args.scenario, args.duration = args.reference, test.scenario, test.duration_s
            config = config_from_args(args)
            end_tick = seconds_to_tick(test.duration_s) if test.duration_s else config.scenario.end_tick
            limits = limits_from_args(args)
            [reference] = g.run_many(
                [args.reference],
                config,
                end_tick,
                jobs=1,
                deadline_s=args.deadline,
                limits=limits,
                timeout_s=args.timeout,
                private=False,
            )
            if not reference.ok:
                raise CliError(
                    f"the reference lab did not run on test {test.name!r}: "
                    f"{reference.message or reference.status}"
                )
            [result] = g.run_many(
                [submission], config, end_tick, deadline_s=args.deadline, limits=limits, executor=executor,
                folders=folders,
            )
            graded = ag.Outcome(
                test, g.grade_result(result, reference, abs_tol=args.abs_tol, rel_tol=args.rel_tol)
            )
            results.append(graded)
            print(
                f"{test.name}: {graded.grade.grade} ({graded.points:g} of {test.points:g} points): "
                f"{for_terminal(graded.grade.detail)}"
            )
    finally:
        executor.close()
    if platform == "gradescope":
        report = ag.gradescope_results(results, seconds=time.monotonic() - start)
    else:
        report = ag.prairielearn_results(results)
    try:
        ag.write_results(out, report)
    except OSError as exc:
        raise CliError(f"{out}: cannot write the results file ({exc.strerror})") from None
    earned, possible = sum(r.points for r in results), sum(r.test.points for r in results)
    print(f"{for_terminal(submission.name)}: {earned:g} of {possible:g} points")
    print(f"crslab grade: {platform} results written to {out}", file=sys.stderr)
    return ExitStatus.OK if all(r.passed for r in results) else ExitStatus.MISMATCH


def _tests(args: argparse.Namespace) -> list[ag.PlatformTest]:
    if args.tests is None:
        if not args.points >= 0:
            raise CliError(f"--points must be >= 0, got {args.points:g}")
        scenario = args.scenario or DEFAULT_SCENARIO
        return [ag.PlatformTest(Path(scenario).stem, scenario, args.duration, args.points)]
    try:
        return ag.load_tests(args.tests)
    except ag.BadTestsFile as exc:
        raise CliError(str(exc)) from None
