"""``crslab traj``: plan a joint trajectory through a waypoint file and write it at 1 kHz.

The CSV it writes has one row per 1 ms tick (t = k ms, from 0 to the first tick at or after the
end) and the columns ``t_s``, then ``q1_rad .. qN_rad`` (joint angles; for the CRS arm the motor
angles that ``lab()`` receives, for the RRR arm its DH angles), ``qd1_rad_s ..`` (velocities),
``qdd1_rad_s2 ..`` (accelerations) and ``jerk1_rad_s3 ..``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from crslab.cli import CliError
from crslab.framework_facts import TICKS_PER_S
from crslab.output_paths import with_parent
from crslab.traj.joint_space import ARMS
from crslab.traj.profiles import PROFILES
from crslab.traj.waypoints import WaypointError, plan_waypoints, read_waypoints

RATE_HZ = TICKS_PER_S
"""The lab's tick rate: one output row per tick."""
DEFAULT_VMAX_RAD_S = 1.0
"""A gentle default joint speed limit (the CRS arm itself is rated up to 210 deg/s)."""


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``traj`` subcommand."""
    traj = sub.add_parser(
        "traj",
        help="plan a 1 kHz joint trajectory through a waypoint file (CSV out, PNG plot)",
        description="Plan rest-to-rest joint moves through the Cartesian points of a waypoint "
        "file (IK with the chosen elbow; reachability and joint limits checked, for the CRS arm "
        "its safety envelope at every tick) and write the trajectory at 1 kHz. The waypoint file "
        "is a CSV with the header x_in,y_in,z_in (inches, for the CRS arm; x_units,y_units,z_units "
        "for the RRR arm of seed 003) and optionally t_s (time at each point, s) or speed_in_s "
        "(average speed from the previous point); '#' lines are comments. Rows without a time go "
        "as fast as --vmax/--amax allow.",
        epilog="Output columns: t_s, q1_rad..qN_rad (CRS: motor angles, as lab() receives them; "
        "RRR: DH joint angles), "
        "qd1_rad_s.., qdd1_rad_s2.., jerk1_rad_s3..; one row per 1 ms tick.",
    )
    traj.add_argument("robot", choices=sorted(ARMS), metavar="ROBOT",
                      help=f"the arm ({', '.join(sorted(ARMS))})")
    traj.add_argument("--waypoints", required=True, type=Path, metavar="PTS.csv",
                      help="the waypoint file")
    traj.add_argument("--profile", choices=list(PROFILES), default="li",
                      help="joint profile between waypoints (default: li, Li's sinusoidal jerk)")
    traj.add_argument("-o", "--output", required=True, type=Path, metavar="TRAJ.csv",
                      help="where to write the trajectory (CSV)")
    traj.add_argument("--plot", type=Path, metavar="TRAJ.png",
                      help="also plot position, velocity, acceleration and jerk per joint")
    traj.add_argument("--elbow", choices=("up", "down"), default="up",
                      help="IK elbow branch (default: up, as in the labs)")
    traj.add_argument("--vmax", type=float, default=DEFAULT_VMAX_RAD_S, metavar="RAD_S",
                      help=f"joint speed limit, rad/s (default {DEFAULT_VMAX_RAD_S:g}; 0 for none)")
    traj.add_argument("--amax", type=float, default=0.0, metavar="RAD_S2",
                      help="joint acceleration limit, rad/s^2 (default: none)")
    traj.set_defaults(func=run_traj)


def _columns(n_joints: int) -> list[str]:
    names = ["t_s"]
    for prefix, unit in (("q", "rad"), ("qd", "rad_s"), ("qdd", "rad_s2"), ("jerk", "rad_s3")):
        names += [f"{prefix}{j + 1}_{unit}" for j in range(n_joints)]
    return names


def run_traj(args: argparse.Namespace) -> int:
    """Plan, write the CSV, optionally plot; print a short summary."""
    for name, value in (("--vmax", args.vmax), ("--amax", args.amax)):
        if not np.isfinite(value) or value < 0:
            raise CliError(f"{name} must be a finite number >= 0 (0 for no limit), got {value:g}")
    arm = ARMS[args.robot]
    try:
        pts = read_waypoints(args.waypoints, length_unit=arm.length_unit)
        plan = plan_waypoints(pts, arm, profile=args.profile, elbow=args.elbow, vmax_rad_s=args.vmax or None,
                              amax_rad_s2=args.amax or None)
    except WaypointError as exc:
        raise CliError(str(exc)) from None
    t, s = plan.trajectory.sample(RATE_HZ)
    table = np.column_stack([t, s.q, s.qd, s.qdd, s.jerk]) + 0.0  # no "-0" in the file
    try:
        np.savetxt(with_parent(args.output), table, fmt="%.12g", delimiter=",",
                   header=",".join(_columns(arm.n_joints)), comments="")
    except OSError as exc:
        raise CliError(f"cannot write {args.output}: {exc.strerror or exc}") from None
    print(f"{args.profile} profile through {len(pts.lines)} waypoints of {args.waypoints}: "
          f"{plan.trajectory.end_s:.3f} s, {t.size} rows at {RATE_HZ} Hz -> {args.output}")
    if args.plot is not None:
        from crslab.traj.trajectory_plot import plot_trajectory

        names = [f"{arm.joint_label} {j + 1}" for j in range(arm.n_joints)]
        try:
            plot_trajectory(t, s, args.plot, title=f"{args.robot}: {args.profile} profile through "
                            f"{args.waypoints.name}", joint_names=names, marks_s=plan.arrival_s)
        except (OSError, ValueError) as exc:
            raise CliError(f"cannot write the plot {args.plot}: {exc}") from None
        print(f"plot -> {args.plot}")
    return 0
