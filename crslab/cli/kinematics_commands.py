"""``crslab fk`` and ``crslab ik`` for the CRS arm (inches and degrees, as the lab prints)."""

from __future__ import annotations

import argparse
import json

import numpy as np

from crslab import crs
from crslab.cli import CliError


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``fk`` and ``ik`` subcommands."""
    fk = sub.add_parser(
        "fk",
        help="CRS forward kinematics: joint angles -> x y z (in)",
        description="Forward kinematics of the CRS arm. Prints x y z in inches, the DH angles "
        "and the motor angles in degrees.",
    )
    given = fk.add_mutually_exclusive_group(required=True)
    given.add_argument("--motor-deg", nargs=3, type=float, metavar=("M1", "M2", "M3"),
                       help="motor angles in degrees (what the lab's encoders read)")
    given.add_argument("--motor-rad", nargs=3, type=float, metavar=("M1", "M2", "M3"),
                       help="motor angles in radians")
    given.add_argument("--dh-deg", nargs=3, type=float, metavar=("T1", "T2", "T3"),
                       help="DH angles in degrees")
    fk.add_argument("--json", action="store_true", help="print one JSON object")
    fk.set_defaults(func=run_fk)

    ik = sub.add_parser(
        "ik",
        help="CRS inverse kinematics: x y z (in) -> DH and motor angles (deg)",
        description="Closed-form inverse kinematics of the CRS arm. An unreachable target "
        "prints why and exits with status 2.",
    )
    ik.add_argument("xyz", nargs=3, type=float, metavar=("X", "Y", "Z"), help="target in inches")
    ik.add_argument("--elbow", choices=("up", "down"), default="up",
                    help="elbow branch (default: up, as in the labs)")
    ik.add_argument("--json", action="store_true", help="print one JSON object")
    ik.set_defaults(func=run_ik)


def _fmt(values: np.ndarray) -> str:
    return " ".join(f"{v + 0.0:8.3f}" for v in values)


def run_fk(args: argparse.Namespace) -> int:
    """Print FK of the given angles."""
    if args.dh_deg is not None:
        motor = crs.dh_to_motor(np.radians(args.dh_deg))
    elif args.motor_deg is not None:
        motor = np.radians(args.motor_deg)
    else:
        motor = np.asarray(args.motor_rad, dtype=float)
    xyz = crs.fk(motor)
    dh_deg = np.degrees(crs.motor_to_dh(motor))
    motor_deg = np.degrees(motor)
    if args.json:
        print(json.dumps({"xyz_in": xyz.tolist(), "dh_deg": dh_deg.tolist(),
                          "motor_deg": motor_deg.tolist()}))
    else:
        print(f"xyz (in)    {_fmt(xyz)}")
        print(f"DH (deg)    {_fmt(dh_deg)}")
        print(f"motor (deg) {_fmt(motor_deg)}")
    return 0


def run_ik(args: argparse.Namespace) -> int:
    """Print IK of the given target, or why it has none."""
    try:
        motor = crs.ik(args.xyz, elbow=args.elbow)
    except crs.UnreachableError as exc:
        raise CliError(str(exc)) from None
    dh_deg = np.degrees(crs.motor_to_dh(motor))
    motor_deg = np.degrees(motor)
    if args.json:
        print(json.dumps({"xyz_in": list(args.xyz), "elbow": args.elbow,
                          "dh_deg": dh_deg.tolist(), "motor_deg": motor_deg.tolist()}))
    else:
        print(f"DH (deg)    {_fmt(dh_deg)}")
        print(f"motor (deg) {_fmt(motor_deg)}")
    return 0
