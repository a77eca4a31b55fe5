"""``crslab identify``: calibrate the simulated arm to a real one from recordings of a known lab."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import TextIO

from crslab.cli import CliError
from crslab.cli.run_options import sandbox_from_args
from crslab.lab.build import LabBuildError, LabForbidden
from crslab.output_paths import ready_to_write, with_parent
from crslab.plant.plant_params import PlantParams, PlantParamsError
from crslab.resources import path as resource_path
from crslab.run.status import RunStatus

CALIBRATION_LAB = resource_path("csrc", "labs", "lab2_square_pid.c")
"""crslab's calibration lab: the controller of the real recording the default arm was fitted to."""


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``identify`` subcommand."""
    from crslab.identify.fit import DEFAULT_FIT, GROUPS, RECORDING_SIGMA_RAD

    p = sub.add_parser(
        "identify",
        help="fit the simulated arm's drive, friction and inertia to experiments on a real arm",
        description="Calibrate crslab's arm to a real one. Give recordings of the real arm (the "
        "course's Simulink export: a .mat file or CSV of time and Simulink_PlotVar1..4, or crslab's own "
        "--csv) and the lab file that produced each, and friction tables (the course's Lab 3 method: "
        "'crslab friction' writes one, from crslab or from a real arm's log), each with its uncertainty. "
        "crslab runs each recording's lab against its arm, lines the run up with the recording (which may "
        "start anywhere, on a drifting clock), predicts each table from the arm's friction, and fits the "
        "plant to all of them together by bounded least squares; then writes a plant file for "
        "'crslab sim --plant FILE'. It prints each experiment's residual before and after, a "
        "cross-validation (fit on one experiment, predict the others) and draws real against simulated.",
    )
    p.add_argument("recordings", type=Path, nargs="+", metavar="EXPERIMENT",
                   help="recordings of the real arm (.mat or .csv) and friction tables (.toml)")
    p.add_argument("--sigma", type=float, action="append", metavar="RAD",
                   help="a recording's uncertainty: how closely the arm should follow it, per sample, rad "
                   f"(once for all recordings or once per recording; default: {RECORDING_SIGMA_RAD:g})")
    p.add_argument("--lab", type=Path, action="append", metavar="FILE",
                   help="the lab file that produced the recordings: once for all of them, or once per "
                   "recording in order (default: crslab's calibration lab, csrc/labs/lab2_square_pid.c)")
    p.add_argument("--map", action="append", metavar="P1,P2,P3",
                   help="which Simulink_PlotVar holds motor angle 1, 2 and 3 ('-' for a joint not "
                   "recorded), once for all recordings or once per recording (default: 1,2,3)")
    groups = "; ".join(f"{g} = {' '.join(v)}" for g, v in GROUPS.items())
    p.add_argument("--fit", default=",".join(DEFAULT_FIT), metavar="NAMES",
                   help=f"plant values to fit, by name or group, comma-separated (default: %(default)s; "
                   f"groups: {groups})")
    p.add_argument("--plant", type=Path, metavar="FILE",
                   help="start from this plant file instead of crslab's arm (what is not fitted stays as "
                   "it says)")
    p.add_argument("--fit-rest", action="store_true",
                   help="also fit each recording's true resting pose (motor angles 2 and 3, within 0.02 rad "
                   "of the lab's offsets)")
    p.add_argument("--from", dest="t_from", type=float, metavar="SECONDS",
                   help="fit only from this many seconds into each recording")
    p.add_argument("--to", dest="t_to", type=float, metavar="SECONDS",
                   help="fit only up to this many seconds into each recording")
    p.add_argument("-o", "--output", type=Path, default=Path("crslab-plant.toml"), metavar="FILE",
                   help="the plant file to write (default: %(default)s)")
    p.add_argument("--plot", type=Path, metavar="FIG",
                   help="real against simulated, per joint (default: the plant file's name with .png)")
    p.add_argument("--jobs", type=int, metavar="N", help="runs at once (default: every core)")
    p.add_argument("--max-iterations", type=int, default=30, metavar="N",
                   help="most evaluations of the residual (default: %(default)s)")
    p.add_argument("--no-cross-validation", action="store_true",
                   help="with several experiments, skip fitting each alone to predict the others")
    p.add_argument("--no-sandbox", action="store_true",
                   help="compile and run the lab without the sandbox, with your own permissions")
    p.set_defaults(func=run_identify)


def _per_recording(values: list | None, n: int, default: object, option: str) -> list:
    if not values:
        return [default] * n
    if len(values) == 1:
        return values * n
    if len(values) != n:
        raise CliError(f"{option} is given {len(values)} times for {n} recordings: give it once, or once per "
                       "recording")
    return values


class FitProgress:
    """A progress bar of the simulated runs (a line every 10 % when not on a terminal)."""

    def __init__(self, stream: TextIO | None = None) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.tty = self.stream.isatty()
        self.start = time.monotonic()
        self.shown = -1

    def __call__(self, runs: int, total: int, rms: float | None) -> None:
        share = min(1.0, runs / max(1, total))
        rms_text = f"  RMS {rms:.4f} rad" if rms is not None else ""
        if self.tty:
            width = 30
            filled = int(width * share)
            self.stream.write(f"\rcrslab identify: [{'#' * filled}{'.' * (width - filled)}] {runs} runs "
                              f"{time.monotonic() - self.start:6.1f} s{rms_text}   ")
        elif int(share * 10) > self.shown:
            self.shown = int(share * 10)
            elapsed = time.monotonic() - self.start
            self.stream.write(f"crslab identify: {runs} runs ({elapsed:.1f} s){rms_text}\n")
        self.stream.flush()

    def done(self) -> None:
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()


def _told_names(names: list[str], told: list[str],
                groups: dict[str, tuple[str, ...]]) -> tuple[list[str], list[str]]:
    """Of the names asked for (values or groups), those a fit to friction tables alone fits (a
    group when any of its values is told) and those it leaves as they were.

    >>> _told_names(["drive", "friction", "Vpos1"], ["coulomb_pos1", "viscous_pos1"],
    ...             {"drive": ("stall_nm1",), "friction": ("coulomb_pos1", "viscous_pos1")})
    (['friction'], ['drive', 'Vpos1'])
    """
    fitted = [n for n in names if any(member in told for member in groups.get(n, (n,)))]
    return fitted, [n for n in names if n not in fitted]


def run_identify(args: argparse.Namespace) -> int:
    """``crslab identify``."""
    from crslab.identify import fit as fitting
    from crslab.identify import report
    from crslab.identify.cross_validation import cross_validate, cross_validation_lines
    from crslab.identify.friction_table import FrictionTableError, load_table
    from crslab.identify.recording import PlotVarMap, RecordingError, read_recording
    from crslab.identify.runs import RunFailed, lab_offsets
    from crslab.regress.grade import default_jobs
    from crslab.run.api import make_config

    table_paths = [r for r in args.recordings if r.suffix.lower() == ".toml"]
    recording_paths = [r for r in args.recordings if r.suffix.lower() != ".toml"]
    n = len(recording_paths)
    if not n and (args.lab or args.map or args.sigma or args.fit_rest or args.t_from is not None
                  or args.t_to is not None):
        raise CliError("--lab, --map, --sigma, --fit-rest, --from and --to are for recordings; only friction "
                       "tables were given")
    labs = _per_recording(args.lab, n, CALIBRATION_LAB, "--lab")
    sigmas = _per_recording(args.sigma, n, fitting.RECORDING_SIGMA_RAD, "--sigma")
    if any(not sigma > 0 for sigma in sigmas):
        raise CliError("--sigma must be above 0 rad")
    try:
        maps = [PlotVarMap.parse(m) for m in _per_recording(args.map, n, "1,2,3", "--map")]
    except ValueError as exc:
        raise CliError(str(exc)) from None
    names = [s.strip() for s in args.fit.split(",") if s.strip()]
    try:
        fitting.check_names(names)
        start = PlantParams.load(args.plant) if args.plant else PlantParams.defaults()
    except (fitting.FitError, PlantParamsError) as exc:
        raise CliError(str(exc)) from None
    jobs = args.jobs if args.jobs is not None else default_jobs()
    if jobs < 1 or args.max_iterations < 1:
        raise CliError("--jobs and --max-iterations must be at least 1")
    try:
        recordings = [read_recording(r, m).window(args.t_from, args.t_to)
                      for r, m in zip(recording_paths, maps)]
        fitting.check_recordings(recordings)
        tables = [fitting.TableSource(load_table(t), str(t)) for t in table_paths]
        announced, untold = names, []
        if not recordings:
            joints = {j for t in tables for j in t.table.rows}
            told = fitting.what_tables_tell(fitting.names_to_fit(names, joints))
            announced, untold = _told_names(names, told, fitting.GROUPS)
    except (RecordingError, fitting.FitError, FrictionTableError) as exc:
        raise CliError(str(exc)) from None
    for target, what_it_is in ((args.output, "plant file"), (args.plot, "plot")):  # before the long fit
        if target is not None:
            try:
                ready_to_write(target)
            except OSError as exc:
                raise CliError(f"{target}: cannot write the {what_it_is} there ({exc.strerror})") from None
    sandboxed = sandbox_from_args(args) if recordings else True
    sources = []
    configs: dict[Path, object] = {}
    for rec, lab, sigma in zip(recordings, labs, sigmas):
        if lab not in configs:
            try:
                config = make_config(lab, "hands_off", startup_delay=False, sandbox=sandboxed)
            except LabBuildError as exc:
                if exc.diagnostics:
                    sys.stderr.write(exc.diagnostics)
                status = RunStatus.FORBIDDEN if isinstance(exc, LabForbidden) else RunStatus.BUILD_ERROR
                raise CliError(str(exc), status.exit_status) from None
            try:
                configs[lab] = (config, lab_offsets(config))
            except RunFailed as exc:
                raise CliError(f"a run of the lab failed: {exc}", status=3) from None
        config, offsets = configs[lab]  # type: ignore[misc]
        sources.append(fitting.Source(rec, config, offsets, sigma))
    what = ", ".join(filter(None, [f"{n} recording{'s' if n != 1 else ''}" if n else "",
                                   f"{len(tables)} friction table{'s' if len(tables) != 1 else ''}"
                                   if tables else ""]))
    alone = (f" ({', '.join(untold)}: not from friction tables alone, which tell only friction and the "
             "motor gain; give a recording)") if untold else ""
    runs_at_once = f", {jobs} runs at a time" if recordings else ""
    print(f"crslab identify: fitting {', '.join(announced)} to {what}{runs_at_once}{alone}", file=sys.stderr)
    progress = FitProgress()
    try:
        result = fitting.fit(sources, names=names, start=start, fit_rest=args.fit_rest, jobs=jobs,
                             max_iterations=args.max_iterations, on_progress=progress, tables=tables)
    except fitting.FitError as exc:
        raise CliError(str(exc)) from None
    except RunFailed as exc:
        raise CliError(f"a run of the lab failed: {exc}", status=3) from None
    finally:
        progress.done()
    fitted_names = [f.name for f in result.values]
    for line in report.values_table(result) + [""] + report.residual_table(result, sources):
        print(line)
    header = report.plant_file_header(result, sources, fitted_names)
    try:
        with_parent(args.output).write_text(result.plant.to_toml(header))
    except OSError as exc:
        raise CliError(f"{args.output}: cannot write the plant file ({exc.strerror})") from None
    figure = args.plot if args.plot is not None else args.output.with_suffix(".png")
    if sources:
        try:
            report.plot_fit(figure, result, sources)
        except (OSError, ValueError) as exc:
            raise CliError(f"{figure}: cannot write the plot ({exc})") from None
    else:
        print("crslab identify: no plot: it draws a recording against its simulated run, and only friction "
              "tables were given", file=sys.stderr)
    if len(sources) + len(tables) > 1 and not args.no_cross_validation:
        print("crslab identify: cross-validation: fitting each experiment alone", file=sys.stderr)
        try:
            predictions = cross_validate(sources, tables, names=names, start=start, joint=result, jobs=jobs,
                                         max_iterations=args.max_iterations,
                                         on_fit=lambda name: print(f"crslab identify: fitting {name} alone",
                                                                   file=sys.stderr))
        except RunFailed as exc:
            raise CliError(f"a run of the lab failed: {exc}", status=3) from None
        print()
        for line in cross_validation_lines(predictions):
            print(line)
    before, after = report.rms_overall(result)
    rms = f"RMS {before:.4f} -> {after:.4f} rad in {result.runs} runs; " if sources else ""
    plot = f" and {figure}" if sources else ""
    print(f"crslab identify: {rms}wrote {args.output}{plot}; use it with: crslab sim --plant {args.output}",
          file=sys.stderr)
    return 0
