"""``crslab debug``: run a lab as ``crslab sim`` does, and stop inside ``lab()`` under gdb (or an
IDE through gdbserver) at a tick, a time or a condition, with simulated time frozen."""

from __future__ import annotations

import argparse
import textwrap
from pathlib import Path

from crslab.cli import CliError
from crslab.cli.introduction import WIDTH, pace_text
from crslab.cli.lab_run import LabRun, end_tick_of, scope_rows_asked
from crslab.cli.live_options import add_live_options
from crslab.cli.run_options import add_run_options, config_from_args, positive
from crslab.cli.sink_options import add_sink_options
from crslab.debug.debugged_run import DebugPlan, DebugSession
from crslab.debug.local_port import PortError
from crslab.debug.programs import DebuggerMissing, debugger_for
from crslab.debug.tracer import TracerError
from crslab.run.status import RunResult, RunStatus
from crslab.scenario.event import seconds_to_tick
from crslab.sinks.at_end import AtEnd
from crslab.sinks.narration import seconds

PREFIX = "crslab debug: "


def port(text: str) -> int:
    """argparse type: a TCP port, 0 for any free one."""
    value = int(text)
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"must be 0..65535, got {text}")
    return value


def tick_number(text: str) -> int:
    """argparse type: a tick (>= 0)."""
    value = int(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text}")
    return value


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``debug`` subcommand."""
    p = sub.add_parser(
        "debug",
        help="run a lab under gdb and stop inside lab() at a tick, a time or a condition",
        description="Run a lab file as 'crslab sim' does, built -O0 -g, and stop inside lab() under gdb, "
        "as Code Composer Studio does on the board, but with simulated time frozen while gdb holds the lab: "
        "the arm, the scenario and every output wait. Inspect and change variables, step, set breakpoints "
        "and continue. Default: stop at the first lab() call. See docs/debugging.md (VS Code, CLion).",
    )
    add_run_options(p)
    where = p.add_argument_group("where to stop").add_mutually_exclusive_group()
    where.add_argument("--break-tick", type=tick_number, metavar="N",
                       help="stop inside lab() at tick N (t = N ms)")
    where.add_argument("--break-time", type=float, metavar="SECONDS",
                       help="stop inside lab() at this simulated time")
    where.add_argument("--break-when", metavar="EXPR",
                       help="stop inside the first lab() call that begins with the C expression EXPR true; "
                       "EXPR sees the lab's globals and lab()'s error flag, e.g. \"mycount == 1234\" or "
                       "\"theta1array[5] > 0.3\"")
    p.add_argument("--debug-on-crash", action="store_true",
                   help="a segfault, abort(), a --sanitize finding or (with --strict) an operation making a "
                   "NaN or an infinity stops in gdb at the lab's line instead of ending the run")
    g = p.add_argument_group("debugger")
    g.add_argument("--gdbserver", type=port, metavar="PORT",
                   help="serve the lab to an IDE (VS Code, CLion) with gdbserver on localhost:PORT instead "
                   "of gdb on this terminal (0: a free port, printed)")
    g.add_argument("--ex", action="append", default=[], metavar="CMD",
                   help="a gdb command to run at the first stop (repeatable), e.g. --ex 'print mycount'")
    g.add_argument("--batch", action="store_true",
                   help="gdb runs the --ex commands and ends; the run goes on to its end (scripts, CI)")
    pace = p.add_mutually_exclusive_group()
    pace.add_argument("--speed", type=positive, metavar="X",
                      help="simulated seconds per wall-clock second once running (default: as fast as it "
                      "can)")
    pace.add_argument("--fast", action="store_true",
                      help="run as fast as the machine can once running (the default; as 'crslab sim "
                      "--fast')")
    p.add_argument("--json", action="store_true", help="print the end-of-run summary as JSON on stderr")
    p.add_argument("--quiet", action="store_true",
                   help="no introduction and no scenario events on stderr (gdb's output stays)")
    add_sink_options(p)
    add_live_options(p)
    p.set_defaults(func=run_debug)


def check_debugger_options(args: argparse.Namespace) -> None:
    """Options that contradict each other (one-line errors, before anything is built)."""
    if args.gdbserver is not None and (args.ex or args.batch):
        raise CliError("--ex and --batch drive gdb on this terminal; with --gdbserver, give commands in "
                       "your debugger")
    if args.batch and not args.ex:
        raise CliError("--batch runs the --ex commands: give at least one")


def plan_from_args(args: argparse.Namespace, first_lab_tick: int, end_tick: int) -> DebugPlan:
    """The debugger's part of the options, the break checked against the run (one-line errors)."""
    tick = args.break_tick
    what = f"--break-tick {args.break_tick}"
    if args.break_time is not None:
        tick = seconds_to_tick(args.break_time)
        what = f"--break-time {args.break_time:g}"
    if tick is not None:
        if tick < first_lab_tick:
            raise CliError(f"{what}: lab() is first called at tick {first_lab_tick} "
                           f"(t = {seconds(first_lab_tick)} s)"
                           + ("; --no-startup-delay calls it from the first tick" if first_lab_tick else ""))
        if tick >= end_tick:
            raise CliError(f"{what}: the run ends at tick {end_tick} (t = {seconds(end_tick)} s); "
                           "give a longer --duration")
    return DebugPlan(break_tick=tick, break_when=args.break_when, on_crash=args.debug_on_crash,
                     strict=args.strict, gdbserver_port=args.gdbserver, commands=tuple(args.ex),
                     batch=args.batch)


def introduction(plan: DebugPlan, *, lab: Path, scenario_name: str, end_tick: int, first_lab_tick: int,
                 speed: float | None) -> str:
    """The paragraph printed before the first tick.

    >>> print(introduction(DebugPlan(break_tick=5000), lab=Path("mylab.c"), scenario_name="tour",
    ...                    end_tick=25000, first_lab_tick=4100, speed=None), end="")
    crslab debug: mylab.c (built -O0 -g) on scenario tour for 25.0 s, as fast as it can, under gdb.
      It stops inside lab() at tick 5000 (t = 5.0 s). A crash stops at the lab's line. Simulated time
      stands still while gdb holds the lab: print VAR, next, step, break LINE, continue; tick shows the
      tick, next-tick runs to the next lab() call, quit lets the run go on without gdb.
    """
    debugger = "under gdb" if plan.console else "for your IDE through gdbserver"
    head = (f"{PREFIX}{lab.name} (built -O0 -g) on scenario {scenario_name} for {seconds(end_tick)} s, "
            f"{pace_text(speed)}, {debugger}.")
    if plan.break_tick is not None:
        stop = f"It stops inside lab() at tick {plan.break_tick} (t = {seconds(plan.break_tick)} s)."
    elif plan.break_when is not None:
        stop = f"It stops inside the first lab() call that begins with {plan.break_when} true."
    elif plan.on_crash and plan.console:
        stop = "It runs until the lab crashes."
    else:
        stop = f"It stops inside the first lab() call (t = {seconds(first_lab_tick)} s)."
    parts = [stop]
    if plan.console:
        nan = ", and so does an operation that makes a NaN or an infinity" if plan.on_crash and plan.strict \
            else ""
        parts.append(f"A crash stops at the lab's line{nan}. Simulated time stands still while gdb holds the "
                     "lab: print VAR, next, step, break LINE, continue; tick shows the tick, next-tick runs "
                     "to the next lab() call, quit lets the run go on without gdb.")
    else:
        crash = ", and a crash after it stops there too" if plan.on_crash else ""
        parts.append("crslab holds the lab there and says the port; your IDE's first stop in lab() is at "
                     f"that tick{crash}. Simulated time stands still while the IDE holds the lab.")
    body = textwrap.fill(" ".join(parts), WIDTH, initial_indent="  ", subsequent_indent="  ")
    return f"{head}\n{body}\n"


def run_debug(args: argparse.Namespace) -> int:
    """``crslab debug``."""
    args.no_stdin = True  # the terminal is gdb's; gdb reads and writes the lab's variables
    check_debugger_options(args)
    try:  # before building anything
        program = debugger_for(console=args.gdbserver is None)
    except DebuggerMissing as exc:
        raise CliError(str(exc)) from None
    config = config_from_args(args, log=scope_rows_asked(args), debug=True, break_when=args.break_when)
    first_lab_tick = config.startup_ticks
    plan = plan_from_args(args, first_lab_tick, end_tick_of(args, config))
    run = LabRun(args, config, "debug")

    def intro(end_tick: int) -> str:
        return introduction(plan, lab=config.build.source, scenario_name=config.scenario.name,
                            end_tick=end_tick, first_lab_tick=first_lab_tick, speed=args.speed)

    def say(line: str) -> None:
        run.stdout.flush()
        run.say(line)

    try:
        with DebugSession(plan, first_lab_tick, say, program) as session:
            def say_unreached(result: RunResult) -> None:
                unreached = session.unreached() if result.status is RunStatus.OK else None
                if unreached:
                    run.say(unreached)

            result = run.run(intro, speed=args.speed, controls=[session], debug=session.setup,
                             debugger=session, ready=session.start, extra_sinks=[AtEnd(say_unreached)],
                             lab_cost=False)
    except PortError as exc:
        raise CliError(f"--gdbserver {args.gdbserver}: {exc}") from None
    except TracerError as exc:
        raise CliError(str(exc)) from None
    return result.exit_status
