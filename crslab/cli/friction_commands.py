"""``crslab friction``: the course's Lab 3 friction identification, on crslab's arm or from a real
arm's Tera Term log, as the course's table (Vpos, Vneg, Cpos, Cneg per joint)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from crslab.cli import CliError
from crslab.cli.run_options import sandbox_from_args
from crslab.output_paths import ready_to_write
from crslab.resources import path as resource_path

COURSE_TABLE = resource_path("models", "crs_arm", "recordings", "lab3_friction_table_course.toml")
"""The course's friction table (what its Lab 3 identification found on the course's arms)."""


def _speeds(text: str) -> list[float]:
    try:
        speeds = [float(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"speeds are numbers separated by commas, got {text!r}") from None
    if not 2 <= len(speeds) <= 9 or any(s <= 0 for s in speeds):
        raise argparse.ArgumentTypeError(f"give 2 to 9 motor speeds above 0 rad/s, got {text!r}")
    return speeds


def _joints(text: str) -> list[int]:
    parts = [p.strip() for p in text.split(",") if p.strip()]
    if not parts or any(p not in ("1", "2", "3") for p in parts):
        raise argparse.ArgumentTypeError(f"joints are 1, 2 and 3 separated by commas, got {text!r}")
    return sorted({int(p) for p in parts})


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``friction`` subcommand."""
    from crslab.identify.friction_table import LAB_SPEEDS_RAD_S

    p = sub.add_parser(
        "friction",
        help="the course's Lab 3 friction identification: the table Vpos, Vneg, Cpos, Cneg per joint",
        description="Measure each joint's friction the course's way: crslab's Lab 3 lab "
        "(csrc/labs/lab3_friction_id.c) drives each joint in turn at constant motor speeds in both "
        "directions with a velocity loop and prints the mean command at each speed; crslab fits the "
        "course's lines u = Vpos w + Cpos and u = Vneg w + Cneg (command units, w in rad/s) and prints "
        "them beside the course's table, with a plot. By default the lab runs on crslab's arm; --log "
        "reads what it printed on a real arm (a Tera Term log) instead, which gives you your arm's table.",
    )
    p.add_argument("--log", type=Path, metavar="FILE",
                   help="a Tera Term log of the lab run on a real arm: fit it instead of running crslab's "
                   "arm")
    p.add_argument("--lab", type=Path, metavar="FILE",
                   help="the lab to run (default: crslab's csrc/labs/lab3_friction_id.c; another lab must "
                   "print the same 'joint N speed W rad/s command U' lines and watch the same variables)")
    p.add_argument("--plant", type=Path, metavar="FILE",
                   help="run on this plant file's arm instead of crslab's (crslab identify writes one)")
    p.add_argument("--joints", type=_joints, default=[1, 2, 3], metavar="J,...",
                   help="the joints to measure (default: 1,2,3)")
    p.add_argument("--speeds", type=_speeds, default=list(LAB_SPEEDS_RAD_S), metavar="W,...",
                   help="the motor speeds, rad/s (default: %(default)s)")
    p.add_argument("--vmin", type=float, default=0.0, metavar="RAD_S",
                   help="fit the lines only to speeds above this (default: every speed)")
    p.add_argument("--reference", type=Path, default=COURSE_TABLE, metavar="TABLE",
                   help="the table to compare with (default: the course's, "
                   "models/crs_arm/recordings/lab3_friction_table_course.toml)")
    p.add_argument("-o", "--output", type=Path, default=Path("crslab-friction.toml"), metavar="FILE",
                   help="write the table here, for 'crslab identify' (default: %(default)s)")
    p.add_argument("--plot", type=Path, metavar="FIG",
                   help="command against speed per joint (default: the table's name with .png)")
    p.add_argument("--no-sandbox", action="store_true",
                   help="compile and run the lab without the sandbox, with your own permissions")
    p.set_defaults(func=run_friction)


def run_friction(args: argparse.Namespace) -> int:
    """``crslab friction``."""
    from crslab.identify.friction_lab import FRICTION_LAB, FrictionRunError, NotAFrictionLab, run_friction_lab
    from crslab.identify.friction_report import plot_table, table_lines
    from crslab.identify.friction_table import FrictionTableError, fit_lines, load_table, parse_points
    from crslab.lab.build import LabBuildError, LabForbidden
    from crslab.plant.plant_params import PlantParams, PlantParamsError
    from crslab.run.status import RunStatus

    try:
        reference = load_table(args.reference)
    except FrictionTableError as exc:
        raise CliError(str(exc)) from None
    figure = args.plot if args.plot is not None else args.output.with_suffix(".png")
    for target, what_it_is in ((args.output, "table"), (figure, "plot")):  # before the long run
        try:
            ready_to_write(target)
        except OSError as exc:
            raise CliError(f"{target}: cannot write the {what_it_is} there ({exc.strerror})") from None
    if args.log is not None:
        if args.lab or args.plant:
            raise CliError("--log fits a real arm's log: --lab and --plant are for a run on crslab's arm")
        try:
            text = args.log.read_text(errors="replace")
        except OSError as exc:
            raise CliError(f"{args.log}: cannot be read ({exc.strerror})") from None
        points, what = parse_points(text), f"the log {args.log}"
        points = [p for p in points if p.joint in args.joints]
    else:
        lab = args.lab if args.lab is not None else FRICTION_LAB
        try:
            plant = PlantParams.load(args.plant) if args.plant else PlantParams.defaults()
        except PlantParamsError as exc:
            raise CliError(str(exc)) from None
        arm = f"the arm of {args.plant}" if args.plant else "crslab's arm"
        what = f"{Path(lab).name} on {arm}"
        print(f"crslab friction: running {what}: joints {','.join(map(str, args.joints))}, "
              f"{len(args.speeds)} speeds each way", file=sys.stderr)

        tty = sys.stderr.isatty()
        shown = [0.0]

        def progress(simulated_s: float, bound_s: float) -> None:
            text = f"crslab friction: {simulated_s:5.0f} s simulated (the lab takes at most {bound_s:.0f} s)"
            if tty:
                sys.stderr.write("\r" + text)
            elif simulated_s >= shown[0] + 100.0:
                shown[0] = simulated_s
                sys.stderr.write(text + "\n")
            sys.stderr.flush()

        try:
            run = run_friction_lab(plant, joints=args.joints, speeds_rad_s=args.speeds, lab=lab,
                                   sandbox=sandbox_from_args(args), on_progress=progress)
        except LabBuildError as exc:
            if exc.diagnostics:
                sys.stderr.write(exc.diagnostics)
            status = RunStatus.FORBIDDEN if isinstance(exc, LabForbidden) else RunStatus.BUILD_ERROR
            raise CliError(str(exc), status.exit_status) from None
        except NotAFrictionLab as exc:
            raise CliError(str(exc)) from None
        except (FrictionRunError, KeyError) as exc:
            raise CliError(f"the run failed: {exc}", status=3) from None
        finally:
            if tty:
                sys.stderr.write("\n")
        points = run.points
    try:
        table = fit_lines(points, args.vmin, source=what)
    except FrictionTableError as exc:
        raise CliError(f"{what}: {exc}") from None
    print(f"friction of {what}, command units against motor speed (rad/s): u = Vpos w + Cpos moving "
          f"positive, u = Vneg w + Cneg moving negative; {len(points)} passes")
    for line in table_lines(table, reference, "course" if args.reference == COURSE_TABLE else "ref"):
        print(line)
    header = f"crslab friction: {what}"
    try:
        args.output.write_text(table.to_toml(header))
    except OSError as exc:
        raise CliError(f"{args.output}: cannot write the table ({exc.strerror})") from None
    try:
        plot_table(figure, table, reference, "real arm" if args.log else "crslab",
                   reference.source or "reference")
    except (OSError, ValueError) as exc:
        raise CliError(f"{figure}: cannot write the plot ({exc})") from None
    print(f"crslab friction: wrote {args.output} and {figure}", file=sys.stderr)
    return 0
