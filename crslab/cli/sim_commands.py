"""``crslab sim``: run a lab file at 1 kHz against the simulated arm, printing like Tera Term."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from crslab.cli import CliError
from crslab.cli.host_options import HostRun, add_host_options
from crslab.cli.live_options import LiveRun, add_live_options, live_needs_log
from crslab.cli.sim_narration import Narrator, introduction
from crslab.cli.tracking_options import TrackingRun, add_tracking_options
from crslab.framework_facts import (
    CPU_CYCLES_PER_TICK,
    LAB_BUDGET_INSTRUCTIONS,
    MB_LIMIT_UNITS,
    MB_OVER_LIMIT_MS,
    MB_TIMEOUT_MS,
    MOTOR_BOARDS,
    SCI_TX_FIFO_CHARS,
    SERIAL_CHARS_PER_MS,
)
from crslab.generations import Generation
from crslab.lab.build import LabBuildError, LabForbidden
from crslab.lab.c28x_check import C28xCheck, first_run_check, remember
from crslab.lab.print_trigger import missing_printing_notice
from crslab.live.console import VarConsole
from crslab.plant.plant_params import PlantParamsError
from crslab.sandbox import missing as sandbox_missing
from crslab.scenario.event import seconds_to_tick
from crslab.scenario.expect_events import summary_text
from crslab.scenario.load import ScenarioError
from crslab.sim.api import DEFAULT_REST_MOTOR_RAD, make_config
from crslab.sim.board_ffi import board_constants
from crslab.sim.config import SimConfig
from crslab.sim.session import DEFAULT_DEADLINE_S, Limits, SimError, Simulation
from crslab.sim.status import RunResult, RunStatus
from crslab.sinks.sink import FanOut, SinkError
from crslab.sinks.stdout import StdoutSink
from crslab.sinks.transcript_file import TranscriptSink
from crslab.untrusted_text import for_terminal, for_text

NEAR_BUDGET = 0.8  # warn when a lab() call took this share of the budget


def positive_int(text: str) -> int:
    """argparse type: a whole number > 0."""
    try:
        value = int(text.replace("_", "").replace(",", ""))
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text}") from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def positive(text: str) -> float:
    """argparse type: a number > 0."""
    value = float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def add_run_options(p: argparse.ArgumentParser) -> None:
    """Options shared by every command that runs a lab (sim, record, check, grade)."""
    p.add_argument("--lab", type=Path, metavar="FILE",
                   help="the lab file (.c, or a .cpp holding C); default: crslab's Lab 1 kinematics lab")
    p.add_argument("--scenario", metavar="NAME|FILE",
                   help="built-in scenario name or TOML file (default: tour; see 'crslab scenarios')")
    p.add_argument("--duration", type=positive, metavar="SECONDS",
                   help="simulated seconds to run (default: until the scenario ends)")
    p.add_argument("--offsets", type=float, nargs=2, metavar=("O2", "O3"),
                   help="the arm's true resting motor angles 2 and 3 in rad (default: the scenario's, "
                   "else {:g} {:g})".format(*DEFAULT_REST_MOTOR_RAD[1:]))
    p.add_argument("--no-startup-delay", action="store_true",
                   help="call lab() from the first tick instead of at 4.1 s")
    p.add_argument("--motor-board", choices=list(MOTOR_BOARDS),
                   help="the motor board between the framework and the arm: piccolo (Gen B's hardware: "
                   f"a joint commanded beyond {MB_LIMIT_UNITS:g} units for {MB_OVER_LIMIT_MS} ms, or "
                   f"{MB_TIMEOUT_MS} ms without a command, cuts every output) or none (Gen A's older, "
                   "undocumented board: commands pass through); default: the lab's generation's")
    p.add_argument("--plant", type=Path, metavar="FILE",
                   help="the arm's plant parameters (drive, friction, variations) from a plant file, as "
                   "'crslab identify' writes for your own arm (default: crslab's arm, fitted to a real one)")
    p.add_argument("--deadline", type=positive, default=DEFAULT_DEADLINE_S, metavar="SECONDS",
                   help="wall-clock time one lab() or printing() call may take before it counts as hung "
                   "(default: %(default)s)")
    p.add_argument("--budget", type=positive_int, default=LAB_BUDGET_INSTRUCTIONS, metavar="INSTRUCTIONS",
                   help="what one lab() call may cost, in WebAssembly instructions (about one per cycle of "
                   "the 150 MHz F28335; a --native run compares the time its lab() takes at that rate; "
                   "default: %(default)s, half a tick)")
    p.add_argument("--strict", action="store_true", help="a NaN or Inf torque ends the run with an error")
    p.add_argument("--native", action="store_true",
                   help="build the lab natively with the host's C compiler instead of as WebAssembly "
                   "(it then runs in the worker process itself, inside the run sandbox)")
    p.add_argument("--sanitize", action="store_true",
                   help="build the lab natively with AddressSanitizer and UBSan and report memory errors")
    p.add_argument("--max-output-mb", type=positive, default=16.0, metavar="MB",
                   help="cut the run off when the lab has printed this much (default: %(default)g)")
    p.add_argument("--mem-limit-mb", type=int, metavar="MB", help="memory limit of the lab's process")
    p.add_argument("--cpu-limit", type=positive, metavar="SECONDS",
                   help="CPU-time limit of the lab's process")
    p.add_argument("--no-sandbox", action="store_true",
                   help="compile and run the lab without the sandbox, with your own permissions (it may "
                   "then read and write your files, start programs and use the network)")


def add_c28x_option(p: argparse.ArgumentParser) -> None:
    """--no-c28x-check (sim, grade)."""
    p.add_argument("--no-c28x-check", action="store_true",
                   help="do not compile the lab a second time with the C28x's widths (int 16 bits, long 32, "
                   "double 32) to report where the board's arithmetic gives another result (sim: on a "
                   "lab's first run; grade: in each report)")


def limits_from_args(args: argparse.Namespace) -> Limits:
    """The worker limits the run options ask for."""
    return Limits(memory_mb=args.mem_limit_mb, cpu_s=args.cpu_limit,
                  output_bytes=int(args.max_output_mb * 1e6))


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
    p.add_argument("-o", "--transcript", type=Path, metavar="FILE", help="save the exact bytes printed")
    p.add_argument("--json", action="store_true", help="print the end-of-run summary as JSON on stderr")
    p.add_argument("--quiet", action="store_true",
                   help="no introduction before the first tick and no scenario events announced on stderr "
                   "(warnings, errors and the summary stay)")
    add_c28x_option(p)
    add_live_options(p)
    add_host_options(p)
    add_tracking_options(p)
    p.set_defaults(func=run_sim)


def sandbox_from_args(args: argparse.Namespace) -> bool:
    """Whether to sandbox the run: always unless ``--no-sandbox`` (with a warning). On a machine
    without the sandbox, ``grade`` refuses to run (a class's files are untrusted) and the other
    commands, which run the user's own file, warn and run without it."""
    command = args.command
    if args.no_sandbox:
        print(f"crslab {command}: warning: --no-sandbox: the lab runs with your permissions (it may read "
              "and write your files, start programs and use the network)", file=sys.stderr)
        return False
    lacking = sandbox_missing()
    if not lacking:
        return True
    text = "; ".join(lacking)
    if command == "grade":
        raise CliError(f"the sandbox cannot run on this machine: it lacks {text}; give --no-sandbox to grade "
                       "without it (every submission then runs with your permissions)")
    print(f"crslab {command}: warning: running without the sandbox: this machine lacks {text}",
          file=sys.stderr)
    return False


def config_from_args(args: argparse.Namespace, *, log: bool = False,
                     rest_motor_rad: tuple[float, float, float] | None = None, debug: bool = False,
                     break_when: str | None = None) -> SimConfig:
    """Build the lab and load the scenario, turning bad input into one-line errors. The resting
    pose is ``rest_motor_rad`` when given, else ``--offsets``', else the scenario's; ``debug`` and
    ``break_when`` build the lab for a debugger (``crslab debug``)."""
    rest = rest_motor_rad or ((DEFAULT_REST_MOTOR_RAD[0], *args.offsets) if args.offsets else None)
    sandboxed = sandbox_from_args(args)
    try:
        return make_config(args.lab, args.scenario, startup_delay=not args.no_startup_delay,
                           rest_motor_rad=rest, log=log, strict=args.strict,
                           budget=args.budget, native=args.native, sanitize=args.sanitize, sandbox=sandboxed,
                           motor_board=args.motor_board, debug=debug, break_when=break_when,
                           plant=getattr(args, "plant", None))
    except LabBuildError as exc:
        if exc.diagnostics:  # the compiler's messages quote the lab's own lines
            sys.stderr.write(for_text(exc.diagnostics).rstrip("\n") + "\n")
        status = RunStatus.FORBIDDEN if isinstance(exc, LabForbidden) else RunStatus.BUILD_ERROR
        raise CliError(str(exc), status.exit_status) from None
    except (ScenarioError, PlantParamsError) as exc:
        raise CliError(str(exc)) from None


def lab_cost(stats: dict, budget: int) -> dict:
    """lab()'s cost per call, in the firmware's unit: WebAssembly instructions, or (native) the
    microseconds it took, with the budget in the same unit (``budget`` is in instructions, one per cycle
    of the 150 MHz F28335)."""
    calls = stats.get("lab_calls", 0)
    instructions = stats.get("cost_unit", board_constants().CRS_COST_INSTRUCTIONS) == \
        board_constants().CRS_COST_INSTRUCTIONS
    scale = 1.0 if instructions else 1e-3  # ns to us
    return {
        "lab_cost_unit": "instructions" if instructions else "us",
        "lab_cost_mean": round(stats.get("lab_cost_total", 0) * scale / calls, 1) if calls else 0.0,
        "lab_cost_max": round(stats.get("lab_cost_max", 0) * scale, 1),
        "lab_max_tick": stats.get("lab_max_tick", 0),
        "budget": budget if instructions else round(budget * 1000 / CPU_CYCLES_PER_TICK, 1),
        "over_budget": stats.get("over_budget", 0),
        "over_budget_ticks": stats.get("first_over_tick", []),
    }


def summary(result: RunResult, wall_s: float, budget: int) -> dict:
    """The end-of-run numbers: time, lab()'s cost, NaN and long-line notices."""
    st = result.stats
    return {
        "status": result.status,
        "message": result.message,
        "simulated_s": result.end_tick / 1000.0,
        "wall_s": round(wall_s, 3),
        "lab_calls": st.get("lab_calls", 0),
        **lab_cost(st, budget),
        "nan_first_tick": st.get("nan_first_tick", -1),
        "nan_first_tau": st.get("nan_first_joint", 0),
        "nan_count": st.get("nan_count", 0),
        "serial_dropped": st.get("serial_dropped", 0),
        "tx_ring_dropped": st.get("tx_dropped", 0),
        "tx_ring_first_drop_tick": st.get("tx_first_drop_tick", -1),
        "console_bytes": st.get("console_bytes", 0),
        "motor_board": st.get("motor_board", ""),
        "motor_board_cutouts": st.get("motor_board_cutouts", 0),
        "expectations_met": sum(e.met for e in result.expectations),
        "expectations_failed": len(result.failed_expectations),
        "expectations_not_reached": sum(not e.reached for e in result.expectations),
        "expectations": [e.as_dict() for e in result.expectations],
    }


def _count(value: float) -> str:
    return f"{value:,.0f}" if value >= 100 else f"{value:.1f}"


def summary_line(info: dict) -> str:
    """The end-of-run summary in one line.

    >>> summary_line({"simulated_s": 25.0, "wall_s": 0.5, "lab_calls": 10, "lab_cost_mean": 1234.0,
    ...               "lab_cost_unit": "instructions", "lab_cost_max": 5678.0, "lab_max_tick": 4100,
    ...               "over_budget": 2, "over_budget_ticks": [5000, 6000], "budget": 75000,
    ...               "motor_board": "piccolo", "motor_board_cutouts": 1})
    '25.000 s simulated in 0.50 s; lab() x10: mean 1,234 instructions, max 5,678 (tick 4100); 2 over ...'
    >>> summary_line({"simulated_s": 1.0, "wall_s": 0.1, "lab_calls": 0, "motor_board": "piccolo",
    ...               "motor_board_cutouts": 2, "expectations_met": 1, "expectations_failed": 1,
    ...               "expectations_not_reached": 0, "expectations": [{}, {}]})
    '1.000 s simulated in 0.10 s; motor board: 2 cut-outs; expectations: 1 met, 1 failed'

    """
    line = f"{info['simulated_s']:.3f} s simulated in {info['wall_s']:.2f} s"
    if info["lab_calls"]:
        unit = info["lab_cost_unit"]
        line += (f"; lab() x{info['lab_calls']}: mean {_count(info['lab_cost_mean'])} {unit}, "
                 f"max {_count(info['lab_cost_max'])} (tick {info['lab_max_tick']}); "
                 f"{info['over_budget']} over the budget of {_count(info['budget'])}")
        if info["over_budget"]:
            line += f" (ticks {', '.join(map(str, info['over_budget_ticks']))})"
    if info.get("motor_board", "none") != "none":
        n = info.get("motor_board_cutouts", 0)
        line += f"; motor board: {n} cut-out{'' if n == 1 else 's'}"
    if info.get("expectations"):
        line += "; " + summary_text(info["expectations_met"], info["expectations_failed"],
                                    info["expectations_not_reached"])
    return line


def lost_serial_notice(lab_name: str, stats: dict) -> str | None:
    """The warning for bytes that left the board but never reached the transcript, if any were lost.

    >>> lost_serial_notice("lab.c", {"serial_dropped": 925696}).split("; ")[1]
    'the 925696 bytes after that are missing from the transcript'
    """
    dropped = stats.get("serial_dropped", 0)
    if not dropped:
        return None
    c = board_constants()
    return (f"warning: {lab_name}'s serial line carried more within one chunk of ticks than crslab keeps "
            f"({c.CRS_SERIAL_CAPACITY} bytes or {c.CRS_MARK_CAPACITY} ticks); "
            f"the {dropped} bytes after that are missing from the transcript")


def near_budget_warning(lab_name: str, info: dict) -> str | None:
    """A warning when no lab() call went over the budget but the slowest came close."""
    if info.get("over_budget", 0) or not info.get("lab_calls"):
        return None
    if info["lab_cost_max"] <= NEAR_BUDGET * info["budget"]:
        return None
    return (f"warning: {lab_name}'s slowest lab() call cost {_count(info['lab_cost_max'])} "
            f"{info['lab_cost_unit']}, close to the budget of {_count(info['budget'])}")


def print_run_notes(prefix: str, lab_name: str, result: RunResult, generation: Generation) -> None:
    """On stderr after a run (``crslab sim`` and ``crslab debug``): its :func:`notices` and its
    failed scenario expectations, one line each."""
    for line in notices(lab_name, result.stats, generation, result.lab_file):
        print(f"{prefix}{for_terminal(line)}", file=sys.stderr)
    for expectation in result.failed_expectations:
        for line in expectation.lines():
            print(f"{prefix}expectation failed: {for_terminal(line)}", file=sys.stderr)


def notices(lab_name: str, stats: dict, generation: Generation, source: Path | None = None) -> list[str]:
    """One-line warnings about the run (printed on stderr); ``source``, the lab file, names the
    function a lab that triggers printing without a ``printing()`` probably meant."""
    out = []
    if source is not None and "lab_symbols" in stats:
        try:
            text = source.read_bytes().decode("utf-8", "replace")
        except OSError:
            text = ""
        missing = missing_printing_notice(
            lab_name, text, has_printing=bool(stats["lab_symbols"] & board_constants().CRS_LAB_HAS_PRINTING),
            triggers=int(stats.get("print_triggers", 0)), generation=generation)
        if missing:
            out.append(missing)
    lost = lost_serial_notice(lab_name, stats)
    if lost:
        out.append(lost)
    if stats.get("console_bytes", 0) > 0:
        out.append(f"note: {lab_name} wrote {stats['console_bytes']} bytes with printf, puts or the like: "
                   "on the board they go to Code Composer Studio's console, not to Tera Term, and crslab "
                   "does not show them (serial_printf(&SerialA, ...) prints to Tera Term)")
    if stats.get("nan_first_tick", -1) >= 0:
        t = stats["nan_first_tick"]
        out.append(f"warning: {lab_name} returned a NaN or Inf in tau{stats['nan_first_joint']} at tick {t} "
                   f"(t = {t / 1000:.3f} s); no torque was applied on that joint for that tick "
                   f"({stats['nan_count']} such torques in all)")
    if stats.get("tx_dropped", 0) > 0:
        t = stats["tx_first_drop_tick"]
        out.append(f"warning: {lab_name} printed faster than the serial line sends "
                   f"({SERIAL_CHARS_PER_MS:g} characters per ms): {stats['tx_dropped']} characters did not "
                   f"fit the board's {generation.tx_ring_chars}-byte transmit ring (and "
                   f"{SCI_TX_FIFO_CHARS}-byte FIFO) and were dropped, as on the real board; the first at "
                   f"tick {t} (t = {t / 1000:.3f} s)")
    return out


def motor_board_line(tick: int, joint: int, off: bool) -> str:
    """What ``crslab sim`` says on stderr when the motor board cuts the outputs or brings them back.

    >>> motor_board_line(4600, 1, True)
    'motor board: every output cut at tick 4600 (t = 4.600 s): joint 1 commanded beyond 4 units for 500 ms'
    >>> motor_board_line(6100, 1, False)
    'motor board: outputs back at tick 6100 (t = 6.100 s)'
    """
    at = f"at tick {tick} (t = {tick / 1000:.3f} s)"
    if not off:
        return f"motor board: outputs back {at}"
    why = (f"joint {joint} commanded beyond {MB_LIMIT_UNITS:g} units for {MB_OVER_LIMIT_MS} ms" if joint
           else f"no command for {MB_TIMEOUT_MS} ms")
    return f"motor board: every output cut {at}: {why}"


def run_sim(args: argparse.Namespace) -> int:
    """``crslab sim``."""
    tracking = TrackingRun(args)
    config = config_from_args(args, log=live_needs_log(args) or tracking.active)
    c28x = None if args.no_c28x_check else first_run_check(config.build.source, sandboxed=config.sandboxed)
    try:
        return _run_sim(args, config, tracking, c28x)
    finally:
        if c28x is not None:
            c28x.close()


def say_c28x_report(check: C28xCheck | None, lab: Path) -> None:
    """The C28x arithmetic check's findings (it compiled while the lab ran), on a lab's first run;
    nothing when it could not run (a header it lacks: it is an extra, not the run)."""
    if check is None:
        return
    report = check.report()
    if not report.skipped:
        for line in report.lines():
            print(f"crslab sim: {line}", file=sys.stderr)
    remember(lab, report)


def _run_sim(args: argparse.Namespace, config: SimConfig, tracking: TrackingRun,
             c28x: C28xCheck | None) -> int:
    live = LiveRun(args, config)
    host = HostRun(args, config)
    end_tick = seconds_to_tick(args.duration) if args.duration else config.scenario.end_tick
    stdout = StdoutSink()
    # the narrator comes first: an event is announced before what the lab printed after it
    narrator = Narrator(config.scenario.events, stdout, quiet=args.quiet)
    out = FanOut([narrator, stdout])
    if args.transcript:
        try:
            out.add(TranscriptSink(args.transcript))
        except OSError as exc:
            raise CliError(f"{args.transcript}: cannot write the transcript ({exc.strerror})") from None
    lab_name = config.build.source.name

    def on_motor_board(tick: int, joint: int, off: bool) -> None:
        narrator.note(tick, f"crslab sim: {motor_board_line(tick, joint, off)}")

    def on_behind(rate: float) -> None:
        print(f"crslab sim: this machine keeps up only {rate:.2f}x real time; running as fast as it can",
              file=sys.stderr)

    start = time.monotonic()
    try:
        with Simulation(config, deadline_s=args.deadline, limits=limits_from_args(args),
                        on_started=live.worker_started) as sim:
            if not sim.defines_lab:
                raise CliError(f"{lab_name} defines no lab() function", status=RunStatus.NO_LAB.exit_status)
            live.start(out)
            host.start(out)
            if tracking.active:
                out.add(tracking.rows)
            end_tick = tracking.start(sim, end_tick, duration_given=bool(args.duration))
            speed = None if args.fast else args.speed
            narrator.say(introduction(
                lab=config.build.source, scenario_name=config.scenario.name,
                scenario_description=config.scenario.description, end_tick=end_tick,
                startup_ticks=config.startup_ticks, speed=speed,
                console=any(isinstance(c, VarConsole) for c in live.controls), waypoints=args.waypoints))
            narrator.reached(0)
            result = sim.run(end_tick, out, speed=speed, controls=[narrator, *live.controls, *host.controls],
                             on_behind=on_behind, on_motor_board=on_motor_board,
                             on_expectation=narrator.judged)
    except SimError as exc:
        raise CliError(str(exc), status=exc.status.exit_status) from None
    finally:
        host.close()
        try:
            out.close()
        except SinkError as exc:
            raise CliError(str(exc)) from None
    wall = time.monotonic() - start
    tracking.finish()
    say_c28x_report(c28x, config.build.source)
    print_run_notes("crslab sim: ", lab_name, result, config.build.generation)
    info = summary(result, wall, args.budget)
    if args.json:
        print(json.dumps(info), file=sys.stderr)
    else:
        print(f"crslab sim: {summary_line(info)}", file=sys.stderr)
    warning = near_budget_warning(lab_name, info)
    if warning:
        print(f"crslab sim: {warning}", file=sys.stderr)
    if result.message:
        print(f"crslab sim: {for_terminal(result.message)}", file=sys.stderr)
    return result.exit_status
