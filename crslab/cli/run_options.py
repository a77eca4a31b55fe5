"""The options every command that runs a lab shares (``sim``, ``debug``, ``record``, ``check``,
``grade``, ``sweep``; ``identify`` and ``friction`` take the sandbox's), and how they become one
run's configuration, limits and sandbox: bad input is a one-line error, never a traceback.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from crslab.cli import CliError
from crslab.framework_facts import (
    LAB_BUDGET_INSTRUCTIONS,
    MB_LIMIT_UNITS,
    MB_OVER_LIMIT_MS,
    MB_TIMEOUT_MS,
    MOTOR_BOARDS,
)
from crslab.lab.build import LabBuildError, LabForbidden
from crslab.plant.plant_params import PlantParamsError
from crslab.run.api import DEFAULT_REST_MOTOR_RAD, make_config
from crslab.run.board_run import DEFAULT_DEADLINE_S, Limits, RunError
from crslab.run.status import RunResult, RunStatus
from crslab.sandbox import missing as sandbox_missing
from crslab.scenario.load import ScenarioError
from crslab.untrusted_text import for_text
from crslab.worker.config import RunConfig
from crslab.world import WorldError


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
                   help="built-in scenario name or TOML file (default: tour, or hands_off in a --world with "
                   "fixtures; see 'crslab scenarios')")
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
    p.add_argument("--world", metavar="NAME|FILE",
                   help="what the arm can touch: a built-in world (none, contest: the final project's "
                   "peg, hole, obstacle, groove and egg) or a world file (docs/worlds.md); default: none")
    p.add_argument("--deadline", type=positive, default=DEFAULT_DEADLINE_S, metavar="SECONDS",
                   help="wall-clock time one lab() or printing() call may take before it counts as hung "
                   "(with --native, less the time it waited for a core on a busy machine; "
                   "default: %(default)s)")
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
                   help="do not compile the lab a second time, for analysis, to report where the C28x's "
                   "widths (int 16 bits, long 32, double 32) change a result (an overflow, a rounding), as "
                   "they do on the board and crslab's WebAssembly board (sim: on a lab's first run; grade: "
                   "in each report)")


def limits_from_args(args: argparse.Namespace) -> Limits:
    """The worker limits the run options ask for."""
    return Limits(memory_mb=args.mem_limit_mb, cpu_s=args.cpu_limit,
                  output_bytes=int(args.max_output_mb * 1e6))




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
                     break_when: str | None = None) -> RunConfig:
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
                           plant=getattr(args, "plant", None), world=getattr(args, "world", None))
    except LabBuildError as exc:
        if exc.diagnostics:  # the compiler's messages quote the lab's own lines
            sys.stderr.write(for_text(exc.diagnostics).rstrip("\n") + "\n")
        status = RunStatus.FORBIDDEN if isinstance(exc, LabForbidden) else RunStatus.BUILD_ERROR
        raise CliError(str(exc), status.exit_status) from None
    except (ScenarioError, PlantParamsError, WorldError) as exc:
        raise CliError(str(exc)) from None


def run_to_end(config: RunConfig, end_tick: int, args: argparse.Namespace) -> RunResult:
    """``config`` run to ``end_tick`` at full speed, with the deadline and limits of ``args``, every
    serial call and the scope log kept (``record``, ``check``, ``contest``): a worker that cannot
    start, or a lab without ``lab()``, is a one-line error with its exit status."""
    from crslab.run.assemble import run_kept

    try:
        result = run_kept(config, end_tick, deadline_s=args.deadline, limits=limits_from_args(args))
    except RunError as exc:
        raise CliError(str(exc), status=exc.exit_status) from None
    if result.status is RunStatus.NO_LAB:
        raise CliError(result.message, status=result.exit_status)
    return result
