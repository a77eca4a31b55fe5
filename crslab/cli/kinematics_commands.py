"""``crslab fk`` and ``crslab ik``: forward and inverse kinematics of every course robot.

``crslab fk ROBOT q...`` and ``crslab ik ROBOT target...`` take any robot from
``crslab/robots/`` (or a robot file's path); angles are degrees unless ``--rad``. Without a
robot name both commands are the CRS arm's, as the lab prints them: ``crslab fk --motor-deg A B
C`` (or ``--motor-rad``, ``--dh-deg``) and ``crslab ik X Y Z [--elbow up|down]`` in inches.
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from crslab import crs, robots
from crslab.chain_ik import ik as numerical_ik
from crslab.cli import CliError
from crslab.closed_ik import OK, SINGULAR_BASE, SINGULAR_CENTRE, STATUS_TEXT, UNREACHABLE
from crslab.rotation import euler_zyx_to_matrix, matrix_to_euler_zyx


def add_param_option(parser: argparse.ArgumentParser) -> None:
    """``--param NAME=VALUE`` (repeatable): override a robot file's parameter."""
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="override a robot parameter, e.g. --param a1=0.8 (repeatable)")


def load_robot(name: str, params: list[str]) -> robots.Robot:
    """The robot by name or path, with ``--param`` overrides; file errors become one line."""
    overrides = {}
    for item in params:
        key, sep, value = item.partition("=")
        try:
            overrides[key.strip()] = float(value)
        except ValueError:
            raise CliError(f"--param wants NAME=VALUE with a number, got {item!r}") from None
        if not sep:
            raise CliError(f"--param wants NAME=VALUE, got {item!r}")
    try:
        return robots.load(name, overrides)
    except robots.RobotFileError as exc:
        raise CliError(str(exc)) from None


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def split_robot(tokens: list[str]) -> tuple[str | None, list[float]]:
    """``[ROBOT] numbers...`` -> (robot or None, numbers)."""
    robot = None
    if tokens and not _is_number(tokens[0]):
        robot, tokens = tokens[0], tokens[1:]
    bad = [t for t in tokens if not _is_number(t)]
    if bad:
        raise CliError(f"{bad[0]!r} is not a number")
    return robot, [float(t) for t in tokens]


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``fk`` and ``ik`` subcommands."""
    fk = sub.add_parser(
        "fk",
        help="forward kinematics: joint angles -> end-effector pose (any robot; CRS by default)",
        description="Forward kinematics. 'crslab fk ROBOT q1 q2 ...' prints the end-effector position, "
        "rotation and Euler ZYX angles of any robot (see 'crslab robots'); angles in degrees unless "
        "--rad. Without a robot it is the CRS arm's: --motor-deg, --motor-rad or --dh-deg.",
    )
    fk.add_argument("values", nargs="*", metavar="[ROBOT] Q",
                    help="robot name or .toml path (default crs), then one angle per joint")
    given = fk.add_mutually_exclusive_group()
    given.add_argument("--motor-deg", nargs=3, type=float, metavar=("M1", "M2", "M3"),
                       help="CRS motor angles in degrees (what the lab's encoders read)")
    given.add_argument("--motor-rad", nargs=3, type=float, metavar=("M1", "M2", "M3"),
                       help="CRS motor angles in radians")
    given.add_argument("--dh-deg", nargs=3, type=float, metavar=("T1", "T2", "T3"),
                       help="CRS DH angles in degrees")
    fk.add_argument("--rad", action="store_true", help="joint angles are in radians (default degrees)")
    fk.add_argument("--json", action="store_true", help="print one JSON object")
    add_param_option(fk)
    fk.set_defaults(func=run_fk)

    ik = sub.add_parser(
        "ik",
        help="inverse kinematics: target -> joint angles (any robot; CRS by default)",
        description="Inverse kinematics. 'crslab ik ROBOT target...': the CRS and RRR arms take X Y Z, the "
        "planar 3R arm X Y PHI, and any other robot X Y Z (position only) or X Y Z A B G (pose with "
        "Euler ZYX angles), solved numerically. Angles in degrees unless --rad. Without a robot: the "
        "CRS arm's closed form, X Y Z in inches. No solution prints why and exits with status 2.",
    )
    ik.add_argument("values", nargs="+", metavar="[ROBOT] TARGET",
                    help="robot (default crs), then the target")
    ik.add_argument("--elbow", choices=("up", "down"), default="up",
                    help="CRS elbow branch (default: up, as in the labs)")
    ik.add_argument("--rad", action="store_true", help="angles in and out in radians (default degrees)")
    ik.add_argument("--json", action="store_true", help="print one JSON object")
    ik.add_argument("--tol", type=float, default=1e-6,
                    help="numerical IK: residual to reach, length unit and rad (default 1e-6)")
    ik.add_argument("--restarts", type=int, default=50, help="numerical IK: random restarts (default 50)")
    ik.add_argument("--seed", type=int, default=0, help="numerical IK: seed of the random starts")
    ik.add_argument("--q0", nargs="+", type=float, metavar="Q", help="numerical IK: first start (angles)")
    add_param_option(ik)
    ik.set_defaults(func=run_ik)


def _fmt(values: np.ndarray) -> str:
    return " ".join(f"{v + 0.0:8.3f}" for v in np.ravel(values))


def _crs_fk(motor: np.ndarray, as_json: bool) -> int:
    xyz = crs.fk(motor)
    dh_deg = np.degrees(crs.motor_to_dh(motor))
    motor_deg = np.degrees(motor)
    if as_json:
        print(json.dumps({"xyz_in": xyz.tolist(), "dh_deg": dh_deg.tolist(),
                          "motor_deg": motor_deg.tolist()}))
    else:
        print(f"xyz (in)    {_fmt(xyz)}")
        print(f"DH (deg)    {_fmt(dh_deg)}")
        print(f"motor (deg) {_fmt(motor_deg)}")
    return 0


def run_fk(args: argparse.Namespace) -> int:
    """Print FK of the given angles."""
    robot_name, q = split_robot(args.values)
    crs_flags = args.dh_deg is not None or args.motor_deg is not None or args.motor_rad is not None
    if crs_flags:
        if q or robot_name not in (None, "crs"):
            raise CliError("--motor-deg, --motor-rad and --dh-deg are the CRS arm's; give either them or "
                           "ROBOT q...")
        if args.dh_deg is not None:
            motor = crs.dh_to_motor(np.radians(args.dh_deg))
        elif args.motor_deg is not None:
            motor = np.radians(args.motor_deg)
        else:
            motor = np.asarray(args.motor_rad, dtype=float)
        return _crs_fk(motor, args.json)
    robot = load_robot(robot_name or "crs", args.param)
    if len(q) != robot.n_joints:
        raise CliError(f"{robot.name} has {robot.n_joints} joints; got {len(q)} angle(s)")
    q_rad = np.asarray(q) if args.rad else np.radians(q)
    pose = robot.fk(q_rad)
    zyx = matrix_to_euler_zyx(pose[:3, :3])
    centres = robot.joint_centres(q_rad)
    angle_key, angles = ("q_rad", q_rad) if args.rad else ("q_deg", np.degrees(q_rad))
    zyx_out = zyx if args.rad else np.degrees(zyx)
    zyx_key = "euler_zyx_rad" if args.rad else "euler_zyx_deg"
    motor = crs.dh_to_motor(q_rad) if robot.closed_form == "crs" else None
    if args.json:
        out = {"robot": robot.name, angle_key: angles.tolist(), "unit": robot.length_unit,
               "position": pose[:3, 3].tolist(), "rotation": pose[:3, :3].tolist(), zyx_key: zyx_out.tolist()}
        if centres is not None:
            out["joint_centres"] = centres.tolist()
        if motor is not None:
            out["motor_deg"] = np.degrees(motor).tolist()
        print(json.dumps(out))
        return 0
    unit = "rad" if args.rad else "deg"
    print(f"robot            {robot.name}: {robot.title}")
    print(f"q ({unit})          {_fmt(angles)}")
    print(f"position ({robot.length_unit})".ljust(17) + _fmt(pose[:3, 3]))
    for i, row in enumerate(pose[:3, :3]):
        print(("rotation" if i == 0 else "").ljust(17) + _fmt(row))
    print(f"euler zyx ({unit})  {_fmt(zyx_out)}")
    if motor is not None:
        print(f"motor (deg)      {_fmt(np.degrees(motor))}")
    if centres is not None:
        print(f"joint centres ({robot.length_unit}), one per DH frame:")
        for name, point in zip(robot.row_names, centres):
            print(f"  {name:<26} {_fmt(point)}")
    return 0


def _crs_ik(xyz: list[float], elbow: str, as_json: bool, rad: bool = False) -> int:
    if len(xyz) != 3:
        raise CliError(f"the CRS arm's IK takes X Y Z in inches; got {len(xyz)} number(s)")
    try:
        motor = crs.ik(xyz, elbow=elbow)
    except crs.UnreachableError as exc:
        raise CliError(str(exc)) from None
    unit = "rad" if rad else "deg"
    dh = crs.motor_to_dh(motor)
    dh_out, motor_out = (dh, motor) if rad else (np.degrees(dh), np.degrees(motor))
    if as_json:
        print(json.dumps({"xyz_in": list(xyz), "elbow": elbow, f"dh_{unit}": dh_out.tolist(),
                          f"motor_{unit}": motor_out.tolist()}))
    else:
        print(f"DH ({unit})    {_fmt(dh_out)}")
        print(f"motor ({unit}) {_fmt(motor_out)}")
    return 0


def _closed_ik(robot: robots.Robot, target: list[float], args: argparse.Namespace) -> int:
    if len(target) != 3:
        what = "X Y PHI" if robot.closed_form == "planar_3r" else "X Y Z"
        raise CliError(f"{robot.name}'s IK takes {what}; got {len(target)} number(s)")
    t = np.asarray(target, dtype=float)
    if robot.closed_form == "planar_3r" and not args.rad:
        t[2] = np.radians(t[2])
    sol = robot.closed_ik(t)
    q_out = sol.q if args.rad else np.degrees(sol.q)
    singular = [text for flag, text in ((SINGULAR_BASE, "target on the base axis: q1 is free (0 shown)"),
                                        (SINGULAR_CENTRE, "on the first moving axis: that joint is free "
                                                          "(0 shown)")) if int(sol.singular) & flag]
    if not np.any(sol.status == OK):
        why = "outside the joint limits" if np.any(sol.status != UNREACHABLE) else "out of reach"
        raise CliError(f"target {tuple(target)} has no solution for {robot.name}: {why}")
    if args.json:
        print(json.dumps({"robot": robot.name, "target": target, "singular": singular,
                          "solutions": [{"branch": name, "status": STATUS_TEXT[int(s)],
                                         ("q_rad" if args.rad else "q_deg"): q.tolist()}
                                        for name, s, q in zip(sol.slot_names, sol.status, q_out)]}))
    else:
        unit = "rad" if args.rad else "deg"
        print(f"robot {robot.name}; joint angles in {unit}")
        for name, s, q in zip(sol.slot_names, sol.status, q_out):
            print(f"  {name:<22} {_fmt(q)}   {STATUS_TEXT[int(s)]}")
        for text in singular:
            print(f"  singular: {text}")
    return 0


def _numerical_ik(robot: robots.Robot, target: list[float], args: argparse.Namespace) -> int:
    if len(target) not in (3, 6):
        raise CliError(f"{robot.name}'s IK takes X Y Z, or X Y Z A B G (Euler ZYX); "
                       f"got {len(target)} number(s)")
    goal = np.eye(4)
    goal[:3, 3] = target[:3]
    if len(target) == 6:
        zyx = np.asarray(target[3:]) if args.rad else np.radians(target[3:])
        goal[:3, :3] = euler_zyx_to_matrix(zyx)
    q0 = None
    if args.q0 is not None:
        if len(args.q0) != robot.n_joints:
            raise CliError(f"--q0 needs {robot.n_joints} angles, got {len(args.q0)}")
        q0 = np.asarray(args.q0) if args.rad else np.radians(args.q0)
    if args.tol <= 0 or args.restarts < 0:
        raise CliError("--tol must be positive and --restarts >= 0")
    sol = numerical_ik(robot.chain, goal, q0, position_only=len(target) == 3, tolerance=args.tol,
                       max_restarts=args.restarts, seed=args.seed)
    if not sol.success:
        raise CliError(f"no solution within tolerance {args.tol:g} after {int(sol.restarts)} restarts "
                       f"(best residual {float(sol.residual):.3g}): the target may be out of reach")
    q_out = sol.q if args.rad else np.degrees(sol.q)
    key = "q_rad" if args.rad else "q_deg"
    if args.json:
        print(json.dumps({"robot": robot.name, "target": target, key: q_out.tolist(),
                          "success": bool(sol.success), "iterations": int(sol.iterations),
                          "restarts": int(sol.restarts), "residual": float(sol.residual)}))
    else:
        print(f"robot {robot.name}; {'position' if len(target) == 3 else 'pose'} target")
        print(f"q ({'rad' if args.rad else 'deg'})   {_fmt(q_out)}")
        print(f"residual  {float(sol.residual):.3g} after {int(sol.iterations)} iterations, "
              f"{int(sol.restarts)} restarts")
    return 0


def run_ik(args: argparse.Namespace) -> int:
    """Print IK of the given target, or why it has none."""
    robot_name, target = split_robot(args.values)
    if robot_name in (None, "crs"):
        return _crs_ik(target, args.elbow, args.json, args.rad)
    robot = load_robot(robot_name, args.param)
    if robot.closed_form is not None:
        return _closed_ik(robot, target, args)
    return _numerical_ik(robot, target, args)
