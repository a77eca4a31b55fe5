"""The egg presses' experiments of issue 37, cause 3 (docs/worlds.md, "What presses do on it").

    tools/egg_presses.py mass      the arm's mass at the tip, vertically, at the egg's pose; the
                                   drives' stiffness there
    tools/egg_presses.py drive     a two-mass model of a press: a rigid drive against a compliant one
    tools/egg_presses.py presses   the contest's style labs' presses and their variants, each on its
                                   bench: the touch's speed and the force held; --scale N/m puts
                                   another scale (what the egg stands in and on) under the egg

``presses`` runs whole contest runs (about 2 s of CPU each); the others take a second.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from pathlib import Path

import mujoco
import numpy as np

from crslab.world import load_world

ROOT = Path(__file__).resolve().parents[1]
ARM_XML = ROOT / "models" / "crs_arm" / "crs_arm.xml"
CONTEST = ROOT / "tests" / "labs" / "contest"
EGG_POSE_M = (0.226, 0.184, 0.30)  # the median team's egg top (the force feedforward's bench)
COURSE_ROTORS = (0.075, 0.0375)  # the course's motor 2 and 3 rotor inertias, kg.m^2
DRIVE_NM_PER_RAD = (0.9e4, 1.0e4, 1.5e4)  # the drives' stiffness (models/crs_arm/README.md)
EGG_N_PER_M = load_world("contest").egg.stiffness_n_per_m  # shell and scale in series (docs/worlds.md)
STATIC_N = 16.9  # the joints' static friction at the tip, down (models/crs_arm/README.md)


def _pose(model: mujoco.MjModel) -> np.ndarray:
    """Joint angles (rad) that put the ``ee`` site at EGG_POSE_M, by Newton steps on its position."""
    data = mujoco.MjData(model)
    site = model.site("ee").id
    q = np.array([0.7, -1.0, 1.5])
    jac = np.zeros((3, model.nv))
    for _ in range(50):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        err = np.array(EGG_POSE_M) - data.site_xpos[site]
        if np.linalg.norm(err) < 1e-10:
            break
        mujoco.mj_jacSite(model, data, jac, None, site)
        q = q + np.linalg.solve(jac, err)
    return q


def tip_mass_kg(model: mujoco.MjModel, q: np.ndarray) -> tuple[float, np.ndarray]:
    """The mass at the tip along z, 1 / (J M^-1 J^T)_zz, and the z row of the site's Jacobian."""
    data = mujoco.MjData(model)
    data.qpos[:] = q
    mujoco.mj_forward(model, data)
    mass = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, mass)
    jac = np.zeros((3, model.nv))
    mujoco.mj_jacSite(model, data, jac, None, model.site("ee").id)
    return 1.0 / float((jac @ np.linalg.solve(mass, jac.T))[2, 2]), jac[2]


def mass() -> None:
    model = mujoco.MjModel.from_xml_path(str(ARM_XML))
    q = _pose(model)
    full, jz = tip_mass_kg(model, q)
    model.dof_armature[:] = 0.0
    model.tendon_armature[:] = 0.0
    links, _ = tip_mass_kg(model, q)
    course = mujoco.MjModel.from_xml_path(str(ARM_XML))
    course.dof_armature[1] = COURSE_ROTORS[0]
    course.tendon_armature[0] = COURSE_ROTORS[1]
    with_course, _ = tip_mass_kg(course, q)
    print(f"egg's pose {EGG_POSE_M} m: joints {np.round(q, 4)} rad")
    print(
        f"mass at the tip, vertically: {full:.2f} kg; links alone {links:.2f} kg, "
        f"rotors {full - links:.2f} kg; with the course's rotor values {with_course:.2f} kg"
    )
    # motor 2 is joint j2 (plus a constant), motor 3 the tendon j2 + j3: dz/dm2 = dz/dj2 - dz/dj3
    dz = (jz[1] - jz[2], jz[2])
    print(f"the tip's vertical motion per motor angle: motor 2 {dz[0]:.3f}, motor 3 {dz[1]:.3f} m/rad")
    for k in DRIVE_NM_PER_RAD:
        tip = k / (dz[0] ** 2 + dz[1] ** 2)
        series = 1.0 / (1.0 / tip + 1.0 / EGG_N_PER_M)
        print(
            f"drives of {k:.1e} N.m/rad: {tip:.3g} N/m at the tip; with the egg {series:.3g} N/m "
            f"({series / EGG_N_PER_M:.2f} of it)"
        )


def two_mass(v: float, drive: float | None, egg_ratio: float, depth: float = 0.005) -> tuple[float, float]:
    """A press along the tip's vertical (down positive, the egg's top at 0): the rotors (4.05 kg)
    carry the static friction and the lab's spring (4.8 kN/m to a target ``depth`` below the top,
    its damper 120 N s/m on the rotors' speed, which the motor encoders read), the drive (``drive``
    N/m, None: rigid) carries them to the links (0.88 kg), which touch the egg (spring EGG_N_PER_M,
    damping ``egg_ratio`` of critical for the whole mass). The target comes down at ``v`` from 10
    mm above, the rotors sliding ``STATIC_N / K`` behind it. Returns (peak, held) egg force, N."""
    rotors, links, spring, damper = 4.05, 0.88, 4800.0, 120.0
    ce = egg_ratio * 2.0 * math.sqrt(EGG_N_PER_M * (rotors + links))
    cd = 0.0 if drive is None else 0.1 * math.sqrt(drive * rotors * links / (rotors + links))
    dt, t_end = 2e-6, 1.5
    xr = xl = -0.010
    vr = vl = v
    start = xr + STATIC_N / spring
    peak = 0.0
    for i in range(int(t_end / dt)):
        target = min(start + v * i * dt, depth)
        vt = v if target < depth else 0.0
        fe = max(0.0, EGG_N_PER_M * xl + ce * vl) if xl > 0 else 0.0
        peak = max(peak, fe)
        f = spring * (target - xr) + damper * (vt - vr)
        if drive is None:
            f -= fe
            m = rotors + links
        else:
            fd = drive * (xr - xl) + cd * (vr - vl)
            f -= fd
            m = rotors
            vl += (fd - fe) / links * dt
            xl += vl * dt
        if vr == 0.0 and abs(f) <= STATIC_N:
            a = 0.0
        else:
            a = (f - math.copysign(STATIC_N, vr if vr != 0.0 else f)) / m
            if vr != 0.0 and (vr + a * dt) * vr < 0.0:  # friction stops it within the step
                vr, a = 0.0, 0.0
        vr += a * dt
        xr += vr * dt
        if drive is None:
            vl, xl = vr, xr
    return peak, (EGG_N_PER_M * xl if xl > 0 else 0.0)


def drive() -> None:
    for ratio in (1.0, 0.1):
        print(f"egg damped at {ratio} of critical:")
        for v in (0.010, 0.015, 0.020, 0.035):
            rigid = two_mass(v, None, ratio)
            soft = two_mass(v, 2.2e5, ratio)
            print(
                f"  touch at {v * 1000:.0f} mm/s: rigid drive peak {rigid[0]:.1f} N held {rigid[1]:.1f} N; "
                f"drive of 2.2e5 N/m peak {soft[0]:.1f} N held {soft[1]:.1f} N"
            )


# The presses the teams used, as the style labs write them, and variants: (name, (style, swaps of
# the lab's text)).
NO_COMPENSATION = (("(void)fc;   /* the friction compensation stays as it is */", "*fc = 0;"),)
FROM_REST = (
    (
        "{EGG_X, EGG_Y, EGG_TOP + 0.003, 0.03, STIFF, 0.0},",
        "{EGG_X, EGG_Y, EGG_TOP + 0.003, 0.03, STIFF, 0.5},",
    ),
)
VARIANTS: dict[str, tuple[str, tuple[tuple[str, str], ...]]] = {
    "position_press (15 mm/s, 5 mm deep, compensation on)": ("position_press", ()),
    "position_press 1.5 mm deep": (
        "position_press",
        (("#define PRESS_DEPTH 0.005", "#define PRESS_DEPTH 0.0015"),),
    ),
    "position_press at 10 mm/s": ("position_press", (("0.015, PRESS", "0.010, PRESS"),)),
    "position_press at 20 mm/s": ("position_press", (("0.015, PRESS", "0.020, PRESS"),)),
    "position_press, no compensation while pressing": ("position_press", NO_COMPENSATION),
    "position_press, no compensation, at 10 mm/s": (
        "position_press",
        NO_COMPENSATION + (("0.015, PRESS", "0.010, PRESS"),),
    ),
    "soft_z_press (begun moving)": ("soft_z_press", ()),
    "soft_z_press begun from rest": ("soft_z_press", FROM_REST),
    "force_feedforward (7.8 N)": ("force_feedforward", ()),
    "force_feedforward with twice the force": (
        "force_feedforward",
        (("float Fpress = 1.3", "float Fpress = 2.6"),),
    ),
}


def presses(scale_n_per_m: float | None) -> None:
    import dataclasses

    from crslab.contest.scorecard import score
    from crslab.run.api import simulate
    from crslab.world.world_facts import TOUCH_N

    with tempfile.TemporaryDirectory() as folder:
        for name, (style, swaps) in VARIANTS.items():
            text = (CONTEST / f"{style}.c").read_text()
            for old, new in swaps:
                if text.count(old) != 1:
                    sys.exit(f"egg_presses: {style}.c no longer holds {old!r} once")
                text = text.replace(old, new)
            lab = Path(folder) / f"{style}_{abs(hash(name))}.c"
            lab.write_text(text)
            world = load_world(CONTEST / f"{style}.toml")
            if scale_n_per_m is not None:
                egg = dataclasses.replace(world.egg, scale_stiffness_n_per_m=scale_n_per_m)
                world = dataclasses.replace(world, egg=egg)
            result = simulate(lab, "hands_off", world=world, log=True, duration_s=26.0)
            if not result.ok:
                sys.exit(f"egg_presses: {name}: {result.diagnosis()}")
            log = result.log
            egg_line = next(line for line in score(log, world).lines() if line.startswith("egg"))
            force = log["egg_force"][:, 0]
            touched = np.flatnonzero(force > TOUCH_N)
            if touched.size:
                k = touched[0]
                speed = log["egg_touch_speed"][k, 0] * 1000
                held = force[min(k + 1000, len(force) - 1)]
                touch = f"touched at {speed:.1f} mm/s, 1 s later {held:.2f} N"
            else:
                touch = "never touched"
            print(f"{name}: {touch}\n  {egg_line}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="tools/egg_presses.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("what", choices=("mass", "drive", "presses"), help="which experiment")
    parser.add_argument(
        "--scale",
        type=float,
        metavar="N_PER_M",
        help="presses: the scale's stiffness instead of each bench's (N/m)",
    )
    args = parser.parse_args(argv)
    if args.what == "presses":
        presses(args.scale)
    else:
        {"mass": mass, "drive": drive}[args.what]()
    return 0


if __name__ == "__main__":
    sys.exit(main())
