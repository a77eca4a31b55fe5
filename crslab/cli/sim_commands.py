"""``crslab sim``: run a lab file at 1 kHz against the simulated arm, printing like Tera Term."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from crslab.cli.host_options import add_host_options
from crslab.cli.introduction import introduction
from crslab.cli.lab_run import LabRun, scope_rows_asked
from crslab.cli.live_options import add_live_options
from crslab.cli.run_options import add_c28x_option, add_run_options, config_from_args, positive
from crslab.cli.sink_options import add_sink_options
from crslab.cli.tracking_options import TrackingRun, add_tracking_options
from crslab.lab.c28x_check import C28xCheck, first_run_check, remember
from crslab.live.console import VarConsole
from crslab.run.board_run import BoardRun
from crslab.sinks.at_end import AtEnd
from crslab.worker.config import RunConfig


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``sim`` subcommand."""
    p = sub.add_parser(
        "sim",
        help="run a lab file against the simulated CRS arm",
        description="Compile a lab file unmodified, call its lab() every simulated millisecond "
        "against a MuJoCo model of the CRS arm, and show what the board prints to Tera Term. "
        "With no arguments: crslab's Lab 1 kinematics lab on the built-in tour.",
    )
    add_run_options(p)
    pace = p.add_mutually_exclusive_group()
    pace.add_argument("--speed", type=positive, default=1.0, metavar="X",
                      help="simulated seconds per wall-clock second (default: 1, real time)")
    pace.add_argument("--fast", action="store_true", help="run as fast as the machine can")
    p.add_argument("--json", action="store_true", help="print the end-of-run summary as JSON on stderr")
    p.add_argument("--quiet", action="store_true",
                   help="no introduction before the first tick and no scenario events announced on stderr "
                   "(warnings, errors and the summary stay)")
    add_c28x_option(p)
    add_sink_options(p)
    add_live_options(p)
    add_host_options(p)
    add_tracking_options(p)
    p.set_defaults(func=run_sim)


def run_sim(args: argparse.Namespace) -> int:
    """``crslab sim``."""
    tracking = TrackingRun(args)
    config = config_from_args(args, log=scope_rows_asked(args) or tracking.active)
    c28x = None if args.no_c28x_check else first_run_check(config.build.source, sandboxed=config.sandboxed)
    try:
        return _run_sim(args, config, tracking, c28x)
    finally:
        if c28x is not None:
            c28x.close()


def say_c28x_report(check: C28xCheck | None, lab: Path, native: bool = False) -> None:
    """The C28x arithmetic check's findings (it compiled while the lab ran), on a lab's first run
    (``native``: of a native build); nothing when it could not run (a header it lacks: it is an
    extra, not the run)."""
    if check is None:
        return
    report = check.report()
    if not report.skipped:
        for line in report.lines(native):
            print(f"crslab sim: {line}", file=sys.stderr)
    remember(lab, report)


def _run_sim(args: argparse.Namespace, config: RunConfig, tracking: TrackingRun,
             c28x: C28xCheck | None) -> int:
    run = LabRun(args, config, "sim", host_ports=True)
    speed = None if args.fast else args.speed

    def follow_waypoints(sim: BoardRun) -> None:
        run.end_tick = tracking.start(sim, run.end_tick, duration_given=bool(args.duration))

    def intro(end_tick: int) -> str:
        return introduction(
            lab=config.build.source, scenario_name=config.scenario.name,
            scenario_description=config.scenario.description, end_tick=end_tick,
            startup_ticks=config.startup_ticks, speed=speed,
            console=any(isinstance(c, VarConsole) for c in run.live.controls), waypoints=args.waypoints)

    said_at_end = [AtEnd(lambda result: tracking.finish()),
                   AtEnd(lambda result: say_c28x_report(c28x, config.build.source, config.build.native))]
    rows = [tracking.rows] if tracking.active else []
    result = run.run(intro, speed=speed, extra_sinks=[*rows, *said_at_end], prepare=follow_waypoints)
    return result.exit_status
