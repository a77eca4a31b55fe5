"""``crslab sweep``: one lab over many variations of the arm and its setup, one table row per run.

Exit statuses: 0 every sample passed, 1 some did not, 2 bad input (a bad ``--vary``, a lab that
does not compile, an unreachable Dask scheduler), 130 interrupted (the finished rows are kept).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from crslab.cli import CliError, did_you_mean
from crslab.cli.executor_options import add_executor_options, executor_from_args
from crslab.cli.regress_commands import add_tolerance_options
from crslab.cli.run_options import add_run_options, config_from_args, limits_from_args
from crslab.framework_facts import TICKS_PER_S
from crslab.lab.build import DEFAULT_LAB, LabBuildError
from crslab.lab.source import LabSource
from crslab.output_paths import with_parent
from crslab.run.api import DEFAULT_REST_MOTOR_RAD
from crslab.run.status import ExitStatus
from crslab.scenario.event import seconds_to_tick
from crslab.sweep import sampling, variations
from crslab.sweep import table as tbl
from crslab.sweep.run_metrics import METRIC_NAMES
from crslab.sweep.sample_job import Row, SweepJob, SweepSpec


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``sweep`` subcommand."""
    p = sub.add_parser(
        "sweep",
        help="run a lab over many variations of the arm and its setup, and tabulate how it fares",
        description="Run one lab file many times, each with the arm and its setup varied (friction, payload, "
        "masses, the true resting pose, encoder noise, the drives' gain, the lab's own watched "
        "variables), and write one row per run: the sample, its values, the run's status and metrics "
        "from its signals (safety-envelope trips, motor-board cut-outs, time at the clamp, RMS and max "
        "of Simulink_PlotVar1-4 and of PlotVar1-3 against PlotVar4, final motor angles, and with "
        "--golden whether the transcript matches). Runs execute in local processes or on a Dask "
        "cluster; the table is the same either way. Exit 0 when every sample passed, 1 otherwise.",
        epilog="names for --vary: " + ", ".join(variations.PLANT_NAMES) + ", var:NAME (a watched variable, "
        "var:NAME[i] for an array element). See docs/sweep.md.",
    )
    add_run_options(p)
    p.add_argument(
        "--vary",
        action="append",
        required=True,
        metavar="NAME=LO:HI",
        help="a quantity to vary over [LO, HI] (repeat for several)",
    )
    how = p.add_mutually_exclusive_group(required=True)
    how.add_argument("--samples", type=int, metavar="N", help="N random samples (seeded; see --method)")
    how.add_argument(
        "--grid", type=int, metavar="M", help="a full grid: M evenly spaced values of each quantity"
    )
    p.add_argument(
        "--method",
        choices=sampling.METHODS,
        default="lhs",
        help="how --samples are drawn: lhs (Latin hypercube) or sobol (scrambled Sobol) "
        "(default: %(default)s)",
    )
    p.add_argument(
        "--seed",
        type=int,
        default=1,
        metavar="K",
        help="seeds the samples and each sample's encoder noise (default: %(default)s)",
    )
    p.add_argument(
        "-o",
        "--output",
        type=Path,
        required=True,
        metavar="FILE",
        help="the table: results.csv or results.parquet",
    )
    p.add_argument(
        "--golden",
        type=Path,
        metavar="FILE",
        help="compare each run's transcript with this golden file (number-aware); the scenario, "
        "duration, resting pose, startup delay and motor board default to its",
    )
    add_tolerance_options(p)
    p.add_argument(
        "--plot", type=Path, metavar="FILE.png",
        help="plot the metrics against each varied quantity, one panel per quantity and metric (a metric "
        "every run has the same value of is left out)"
    )
    p.add_argument(
        "--plot-metrics", metavar="NAME,...",
        help="the metrics --plot draws (default: up to 4 of safety_trips, motor_board_cutouts, "
        "plotvar1..3_err_rms, clamp_share that vary); the table's columns name them all"
    )
    add_executor_options(p, "sample")
    p.set_defaults(func=run_sweep)


def _golden(args: argparse.Namespace) -> bytes | None:
    """Read ``--golden``; its recorded options become the defaults of the ones not given."""
    if args.golden is None:
        return None
    from crslab.regress.transcript import GoldenError, read_golden, recorded_run

    try:
        golden = read_golden(args.golden)
        run = recorded_run(golden, [Path.cwd()]).overridden(
            scenario=args.scenario,
            duration_s=args.duration,
            rest_motor_rad=(DEFAULT_REST_MOTOR_RAD[0], *args.offsets) if args.offsets else None,
            startup_delay=False if args.no_startup_delay else None,
            motor_board=args.motor_board,
            world=args.world,
        )
    except GoldenError as exc:
        raise CliError(str(exc)) from None
    args.scenario, args.duration = run.scenario, run.duration_s
    args.no_startup_delay = run.startup_delay is False
    args.motor_board = run.motor_board
    args.world = run.world
    if run.rest_motor_rad is not None and not args.offsets:
        args.offsets = list(run.rest_motor_rad[1:])
    return golden.body


def _plot_metrics(args: argparse.Namespace) -> list[str] | None:
    """``--plot-metrics``, checked against the table's metric names."""
    if args.plot_metrics is None:
        return None
    if args.plot is None:
        raise CliError("--plot-metrics chooses what --plot draws: give --plot FILE.png too")
    names = [n.strip() for n in args.plot_metrics.split(",") if n.strip()]
    for name in names:
        if name not in METRIC_NAMES and name != "end_s":
            raise CliError(f"--plot-metrics: no metric {name!r}{did_you_mean(name, METRIC_NAMES)}; the "
                           "metrics are the table's columns from safety_trips on")
    if not names:
        raise CliError("--plot-metrics: name at least one metric")
    return names


def run_sweep(args: argparse.Namespace) -> int:
    """``crslab sweep``."""
    try:
        parsed = [variations.parse_vary(text) for text in args.vary]
    except variations.VaryError as exc:
        raise CliError(str(exc)) from None
    output: Path = args.output
    if output.suffix.lower() not in tbl.FORMATS:
        raise CliError(f"{output}: the table must be a .csv or a .parquet file")
    if args.plot is not None and args.plot.suffix.lower() not in (".png", ".pdf", ".svg"):
        raise CliError(f"{args.plot}: the plot must be a .png, .pdf or .svg file")
    asked = _plot_metrics(args)
    golden = _golden(args)
    config = config_from_args(args)
    lab_path = args.lab if args.lab is not None else DEFAULT_LAB
    try:
        source = LabSource.read(lab_path)
    except LabBuildError as exc:
        raise CliError(str(exc)) from None
    try:
        varies = tuple(variations.check(parsed, config.build.watched, source.name))
    except variations.VaryError as exc:
        raise CliError(str(exc)) from None
    try:
        units = sampling.samples(
            "grid" if args.grid is not None else args.method,
            len(varies),
            n=args.samples,
            levels=args.grid,
            seed=args.seed,
            fixed=[v.low == v.high for v in varies],
        )
    except ValueError as exc:
        raise CliError(str(exc)) from None
    end_tick = seconds_to_tick(args.duration) if args.duration else config.scenario.end_tick
    spec = SweepSpec(
        lab=source,
        config=config,
        end_tick=end_tick,
        varies=varies,
        seed=args.seed,
        deadline_s=args.deadline,
        limits=limits_from_args(args),
        golden=golden,
        abs_tol=args.abs_tol,
        rel_tol=args.rel_tol,
    )
    jobs = [
        SweepJob(spec, i, tuple(v.value_at(float(u)) for v, u in zip(varies, row, strict=True)))
        for i, row in enumerate(units)
    ]
    columns = spec.columns()
    journal_file = tbl.journal_path(output)
    try:
        with_parent(output)
        journal = tbl.Journal(journal_file, columns)
    except OSError as exc:
        raise CliError(f"{output}: cannot write the table there ({exc.strerror})") from None
    executor = None
    rows: list[Row] = []
    interrupted = False
    try:
        executor = executor_from_args(args)
        how = (
            f"{args.grid}-level grid" if args.grid is not None else f"{args.method} samples, seed {args.seed}"
        )
        print(
            f"crslab sweep: {len(jobs)} runs of {source.name} on {config.scenario.name} "
            f"({end_tick / TICKS_PER_S:.3f} s each; {how}), {executor.description}",
            file=sys.stderr,
        )
        from crslab.regress.grade import Progress

        progress = Progress(len(jobs))

        def on_done(index: int, row: Row) -> None:
            rows.append(row)
            journal.add(row)
            progress.update(jobs[index].name, str(row["status"]))

        try:
            executor.run(jobs, on_done)
        except KeyboardInterrupt:
            interrupted = True
            print(file=sys.stderr)
    finally:
        if executor is not None:
            executor.close()
        journal.close()
        if executor is None:
            journal_file.unlink(missing_ok=True)
    try:
        tbl.write_table(output, columns, rows)
    except OSError as exc:
        raise CliError(
            f"{output}: cannot write the table ({exc.strerror}); the finished rows are in {journal_file}"
        ) from None
    journal_file.unlink(missing_ok=True)
    ordered = sorted(rows, key=lambda r: int(r["sample"]))  # type: ignore[call-overload]
    title = f"{source.name} on {config.scenario.name}: {len(rows)} runs"
    if args.plot is not None and rows:
        drawn, constant = tbl.plot_metrics(ordered, asked)
        for name in constant:
            print(f"crslab sweep: --plot leaves out {name}: every run has the same value "
                  f"({ordered[0][name]})", file=sys.stderr)
        try:
            tbl.plot(args.plot, ordered, varies, title=title, metrics=drawn or ["end_s"])
        except OSError as exc:
            raise CliError(f"{args.plot}: cannot write the plot ({exc.strerror})") from None
    print(f"crslab sweep: {title}")
    for v in varies:
        print(f"  {v.name:<22} {v.low:g} .. {v.high:g}")
    for line in tbl.summary(ordered, varies, total=len(jobs), golden=golden is not None):
        print(line)
    nothing_passed = ordered and not any(r["passed"] for r in ordered)
    if args.lab is None and config.scenario.name == "tour" and nothing_passed:
        print("note: nothing passed: crslab's own Lab 1 (the lab without --lab) applies no torque, so on the "
              "tour, where a hand moves the arm about and lets go, it stays in the safety envelope only "
              "where friction holds it; that is the lab, not your setup: sweep your own lab with --lab FILE")
    where = f" and {args.plot}" if args.plot is not None and rows else ""
    print(f"crslab sweep: {len(rows)} rows written to {output}{where}", file=sys.stderr)
    if interrupted:
        print(
            f"crslab sweep: interrupted after {len(rows)} of {len(jobs)} runs; the finished rows are in "
            f"{output}",
            file=sys.stderr,
        )
        return ExitStatus.INTERRUPTED
    return ExitStatus.OK if all(r["passed"] for r in rows) else ExitStatus.MISMATCH
