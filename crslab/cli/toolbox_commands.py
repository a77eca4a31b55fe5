"""``crslab robots``, ``crslab workspace`` and ``crslab rot``: the rest of the kinematics toolbox."""

from __future__ import annotations

import argparse
import json

import numpy as np

from crslab import robots, workspace
from crslab.cli import CliError
from crslab.cli.kinematics_commands import add_param_option, load_robot
from crslab.rotation import (
    RotationError,
    axis_angle_to_matrix,
    check_rotation,
    euler_zyx_to_matrix,
    matrix_to_axis_angle,
    matrix_to_euler_zyx,
)


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``robots``, ``workspace`` and ``rot`` subcommands."""
    rb = sub.add_parser("robots", help="list the robots that fk, ik and workspace know",
                        description="List the built-in robot files (crslab/robots/*.toml).")
    rb.add_argument("--json", action="store_true", help="print one JSON list")
    rb.set_defaults(func=run_robots)

    ws = sub.add_parser("workspace", help="plot a robot's reachable workspace to a PNG",
                        description="Sample random in-limit configurations of a robot and plot where its "
                        "end effector goes. --dextrous adds the planar 3R arm's dextrous workspace.")
    ws.add_argument("robot", help="robot name (see 'crslab robots') or .toml path")
    ws.add_argument("-o", "--output", required=True, metavar="PNG", help="image file to write")
    ws.add_argument("--samples", type=int, default=20000, help="configurations to sample (default 20000)")
    ws.add_argument("--dextrous", action="store_true", help="also the dextrous workspace (planar 3R)")
    ws.add_argument("--seed", type=int, default=0, help="seed of the sampling")
    add_param_option(ws)
    ws.set_defaults(func=run_workspace)

    rot = sub.add_parser("rot", help="convert between Euler ZYX, axis-angle and rotation matrices",
                         description="Give one rotation; prints it as a matrix, Euler ZYX angles "
                         "(R = Rz(A) Ry(B) Rx(G)) and axis-angle. Angles in degrees unless --rad. A "
                         "matrix that is not a rotation is rejected.")
    given = rot.add_mutually_exclusive_group(required=True)
    given.add_argument("--euler-zyx", nargs=3, type=float, metavar=("A", "B", "G"),
                       help="Euler ZYX angles: about z, then the new y, then the newest x")
    given.add_argument("--axis-angle", nargs=4, type=float, metavar=("X", "Y", "Z", "ANGLE"),
                       help="rotation axis (any length) and angle")
    given.add_argument("--matrix", nargs=9, type=float, metavar="R",
                       help="the 9 entries of a rotation matrix, row by row")
    rot.add_argument("--rad", action="store_true", help="angles in and out in radians (default degrees)")
    rot.add_argument("--json", action="store_true", help="print one JSON object")
    rot.set_defaults(func=run_rot)


def run_robots(args: argparse.Namespace) -> int:
    """Print the robot table."""
    rows = []
    for name in robots.names():
        try:
            r = robots.load(name)
        except robots.RobotFileError as exc:
            raise CliError(str(exc)) from None
        rows.append({"name": r.name, "joints": r.n_joints, "convention": r.convention, "unit": r.length_unit,
                     "ik": r.closed_form or "numerical", "title": r.title, "file": str(r.path)})
    if args.json:
        print(json.dumps(rows))
        return 0
    print(f"{'robot':<11} {'joints':>6}  {'DH':<9} {'unit':<6} {'IK':<12} description")
    for r in rows:
        print(f"{r['name']:<11} {r['joints']:>6}  {r['convention']:<9} {r['unit']:<6} {r['ik']:<12} "
              f"{r['title']}")
    print("Use a name with fk, ik and workspace, or the path of your own robot file "
          "(format: crslab/robots/README.md).")
    return 0


def run_workspace(args: argparse.Namespace) -> int:
    """Write the workspace PNG."""
    robot = load_robot(args.robot, args.param)
    if args.samples < 1:
        raise CliError("--samples must be at least 1")
    if not args.output.lower().endswith(".png"):
        raise CliError(f"-o wants a .png file name, got {args.output!r}")
    try:
        path = workspace.plot(robot, args.output, n=args.samples, dextrous=args.dextrous, seed=args.seed)
    except ValueError as exc:
        raise CliError(str(exc)) from None
    except OSError as exc:
        raise CliError(f"cannot write {args.output}: {exc.strerror}") from None
    print(f"wrote {path} ({args.samples} configurations of {robot.name})")
    return 0


def run_rot(args: argparse.Namespace) -> int:
    """Print one rotation in all three forms."""
    to_rad = (lambda v: np.asarray(v, dtype=float)) if args.rad else np.radians
    from_rad = (lambda v: v) if args.rad else np.degrees
    try:
        if args.euler_zyx is not None:
            r = euler_zyx_to_matrix(to_rad(args.euler_zyx))
        elif args.axis_angle is not None:
            r = axis_angle_to_matrix(args.axis_angle[:3], to_rad(args.axis_angle[3]))
        else:
            r = check_rotation(np.reshape(args.matrix, (3, 3)))
        zyx, singular = matrix_to_euler_zyx(r, return_singular=True)
        axis, angle = matrix_to_axis_angle(r)
    except RotationError as exc:
        raise CliError(str(exc)) from None
    unit = "rad" if args.rad else "deg"
    if args.json:
        print(json.dumps({"matrix": r.tolist(), f"euler_zyx_{unit}": from_rad(zyx).tolist(),
                          "euler_singular": bool(singular), "axis": axis.tolist(),
                          f"angle_{unit}": float(from_rad(angle))}))
        return 0
    for i, row in enumerate(r):
        print(("matrix" if i == 0 else "").ljust(18) + " ".join(f"{v + 0.0:10.6f}" for v in row))
    note = "   (gimbal lock: A = 0, G carries the turn)" if singular else ""
    print(f"euler zyx ({unit})".ljust(18) + " ".join(f"{v + 0.0:10.4f}" for v in from_rad(zyx)) + note)
    print("axis".ljust(18) + " ".join(f"{v + 0.0:10.6f}" for v in axis))
    print(f"angle ({unit})".ljust(18) + f"{float(from_rad(angle)) + 0.0:10.4f}")
    return 0
