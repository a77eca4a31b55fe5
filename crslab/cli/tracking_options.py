"""``crslab sim --waypoints pts.csv``: follow a waypoint file with the tracking lab and report
how well the arm tracked it (max and RMS error per joint, time in torque saturation)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from crslab.cli import CliError
from crslab.framework_facts import TICKS_PER_S
from crslab.run.running import RunningLab
from crslab.sinks.memory import MemorySink
from crslab.traj.profiles import PROFILES
from crslab.traj.tracking import TRACKING_LAB, TrackingError, plot_tracking, tracking_report, write_plan
from crslab.traj.waypoints import WaypointError, WaypointPlan, plan_waypoints, read_waypoints

END_MARGIN_S = 1.0  # simulated seconds kept after the last waypoint


def add_tracking_options(p: argparse.ArgumentParser) -> None:
    """The waypoint-tracking options of ``crslab sim``."""
    g = p.add_argument_group("waypoint tracking")
    g.add_argument("--waypoints", type=Path, metavar="CSV",
                   help="follow this waypoint file (x_in,y_in,z_in[,t_s|speed_in_s]) with the tracking "
                   f"lab (default lab with it: {TRACKING_LAB.name}) and report the tracking error")
    g.add_argument("--profile", choices=sorted(PROFILES), default="li",
                   help="trajectory profile between waypoints (default: %(default)s)")
    g.add_argument("--vmax", type=float, default=1.0, metavar="RAD_S",
                   help="joint speed limit the waypoints are planned with (default: %(default)g)")
    g.add_argument("--plot-tracking", type=Path, metavar="PNG", help="plot desired against actual angles")


class TrackingRun:
    """The waypoint plan of one ``crslab sim`` run, and its report afterwards."""

    def __init__(self, args: argparse.Namespace) -> None:
        self.args = args
        self.plan: WaypointPlan | None = None
        self.rows = MemorySink()
        """The run's scope rows, for the report: feed it the run's output when :attr:`active`."""
        self.path_start_tick = 0
        if args.waypoints is None:
            if args.plot_tracking is not None:
                raise CliError("--plot-tracking needs --waypoints")
            return
        try:
            self.plan = plan_waypoints(read_waypoints(args.waypoints), "crs", profile=args.profile,
                                       vmax_rad_s=args.vmax or None)
        except WaypointError as exc:
            raise CliError(str(exc)) from None
        if args.lab is None:
            args.lab = TRACKING_LAB
        if args.scenario is None:
            args.scenario = "hands_off"

    @property
    def active(self) -> bool:
        """True when the run follows waypoints (and so needs the scope log)."""
        return self.plan is not None

    def start(self, sim: RunningLab, end_tick: int, duration_given: bool) -> int:
        """Write the plan into the lab; returns the run's end tick."""
        if self.plan is None:
            return end_tick
        try:
            path_start_s = write_plan(sim, self.plan, self.args.vmax or None)
        except TrackingError as exc:
            raise CliError(str(exc)) from None
        self.path_start_tick = sim.config.startup_ticks + int(round(path_start_s * TICKS_PER_S))
        if duration_given:
            return end_tick
        return self.path_start_tick + int(round((self.plan.trajectory.end_s + END_MARGIN_S) * TICKS_PER_S))

    def finish(self) -> None:
        """Print the tracking report (stderr) and draw the plot."""
        log = self.rows.log
        if self.plan is None or log is None:
            return
        try:
            report = tracking_report(log, self.plan, self.path_start_tick)
        except TrackingError as exc:
            print(f"crslab sim: {exc}", file=sys.stderr)
            return
        for line in report.lines():
            print(f"crslab sim: tracking {line}", file=sys.stderr)
        if self.args.plot_tracking is not None:
            plot_tracking(report, self.args.plot_tracking)
