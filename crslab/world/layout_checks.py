"""Where a world's fixtures stand, as solids, and the checks that refuse a layout that cannot be
built: fixtures that overlap each other, a fixture where the arm rests, a point the peg must reach
that the arm cannot (docs/worlds.md, "the world file").

The solids of :func:`fixture_solids` are the scene's own (crslab/world/scene.py builds its geoms
from them; the hole block, drawn as staves around its hole, is its bounding box here).

>>> from crslab.world.world_file import load_world
>>> world = load_world("contest")
>>> sorted({table for table, _ in fixture_solids(world)})
['egg', 'groove', 'hole', 'obstacle']
>>> arm_points_m(world, [0.0, 0.0, 0.0])["wrist"].round(4).tolist()   # motor zero, the arm raised
[0.254, 0.0, 0.608]
"""

from __future__ import annotations

import functools
import math
import xml.etree.ElementTree as ET
from collections.abc import Callable

import numpy as np

from crslab import crs
from crslab.plant.model_files import ARM_XML
from crslab.world.fixtures import Triple, World
from crslab.world.groove_plate import floor_boxes, top_boxes
from crslab.world.shapes import Box, Cylinder, Shape, overlap

SCALE_STAND_SHARE = 0.6
"""The scale's stand is a column this share of the platform's diameter across."""
Fail = Callable[[str, str], Exception]
"""How a check reports a problem: ``fail(table, why)`` makes the exception to raise."""


def _column(
    name: str,
    xy: tuple[float, float],
    half_xy: tuple[float, float],
    z0: float,
    z1: float,
    yaw_rad: float = 0.0,
) -> Box:
    return Box((xy[0], xy[1], (z0 + z1) / 2), (half_xy[0], half_xy[1], (z1 - z0) / 2), yaw_rad, name)


def fixture_solids(world: World) -> list[tuple[str, Shape]]:
    """Every fixture's solid parts with the table of the world file they come from (the table
    itself is left out: everything stands on it). Stands reach down to the table."""
    floor = world.floor_z_m
    out: list[tuple[str, Shape]] = []
    if (h := world.hole) is not None:
        bx, by = h.block_size_xy_m
        out.append(("hole", _column("hole_block", h.center_xy_m, (bx / 2, by / 2), floor, h.top_z_m)))
    if (o := world.obstacle) is not None:
        sx, sy = o.size_xy_m
        out.append(("obstacle", _column("obstacle", o.center_xy_m, (sx / 2, sy / 2), floor, o.top_z_m)))
    if (g := world.groove) is not None:
        out += [("groove", b) for b in top_boxes(g)]
        strips = floor_boxes(g)
        out += [("groove", b) for b in strips]
        bottom = g.top_z_m - g.plate_thickness_m
        if bottom > floor:
            out += [
                (
                    "groove",
                    _column(
                        f"groove_stand{i}", s.center[:2], (s.half[0], g.width_m / 2), floor, bottom, s.yaw_rad
                    ),
                )
                for i, s in enumerate(strips)
            ]
    if (e := world.egg) is not None:
        out.append(("egg", Cylinder(e.center_xy_m, e.diameter_m / 2, e.scale_top_z_m, e.top_z_m, "egg")))
        scale_bottom = e.scale_top_z_m - e.scale_height_m
        out.append(
            ("egg", Cylinder(e.center_xy_m, e.scale_diameter_m / 2, scale_bottom, e.scale_top_z_m, "scale"))
        )
        if scale_bottom > floor:
            out.append(
                (
                    "egg",
                    Cylinder(
                        e.center_xy_m,
                        e.scale_diameter_m * SCALE_STAND_SHARE / 2,
                        floor,
                        scale_bottom,
                        "scale_stand",
                    ),
                )
            )
    return out


WHAT = {
    "hole_block": "the hole block",
    "obstacle": "the obstacle",
    "egg": "the egg",
    "scale": "the egg's scale",
    "scale_stand": "the scale's stand",
}


def what(shape: Shape) -> str:
    """A solid in words: ``the hole block``, ``the groove plate``..."""
    if shape.name.startswith("groove_stand"):
        return "the groove plate's stand"
    if shape.name.startswith("groove"):
        return "the groove plate"
    return WHAT.get(shape.name, shape.name)


@functools.cache
def _arm_link_radii_m() -> dict[str, float]:
    """The radii of the arm's links, as the arm's model draws them (models/crs_arm/crs_arm.xml)."""
    sizes = {g.get("name"): float(g.get("size", "0").split()[0]) for g in ET.parse(ARM_XML).iter("geom")}
    return {
        "pedestal": sizes["pedestal"],
        "waist": sizes["waist_column"],
        "upper arm": sizes["upper_arm_link"],
        "forearm": sizes["forearm_link"],
    }


def arm_link_radius_m(link: str) -> float:
    """The radius (m) of one of the arm's links (``pedestal``, ``waist``, ``upper arm``, ``forearm``).

    >>> arm_link_radius_m("forearm")
    0.032
    """
    return _arm_link_radii_m()[link]


def arm_points_m(world: World, motor_rad: object) -> dict[str, np.ndarray]:
    """The arm's points (m, the world file's frame) at motor angles ``motor_rad``: its base,
    shoulder, elbow and wrist (the course's links, raised by :attr:`World.arm_raised_m`), and the
    peg's tip (the course's forward kinematics)."""
    q = np.asarray(motor_rad, dtype=float)
    m = crs.M_PER_IN
    up = np.array([0.0, 0.0, world.arm_raised_m])
    tip = crs.fk(q) * m
    shoulder = np.array([0.0, 0.0, crs.BASE_HEIGHT_IN * m]) + up
    upper = (
        crs.UPPER_ARM_IN
        * m
        * np.array([np.sin(q[1]) * np.cos(q[0]), np.sin(q[1]) * np.sin(q[0]), np.cos(q[1])])
    )
    return {"base": up.copy(), "shoulder": shoulder, "elbow": shoulder + upper, "wrist": tip + up, "tip": tip}


def arm_links_m(world: World, motor_rad: object) -> list[tuple[str, np.ndarray, float]]:
    """The arm's solid parts at ``motor_rad`` as points along their axes (400 each) and radii: the
    model's capsules, and the peg and its gripper below the wrist."""
    p = arm_points_m(world, motor_rad)
    radii = _arm_link_radii_m()

    def along(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return a + np.linspace(0.0, 1.0, 400)[:, None] * (b - a)

    links = [
        ("pedestal", along(p["base"], p["base"] + (0.0, 0.0, 0.12)), radii["pedestal"]),
        ("waist", along(p["base"], p["shoulder"]), radii["waist"]),
        ("upper arm", along(p["shoulder"], p["elbow"]), radii["upper arm"]),
        ("forearm", along(p["elbow"], p["wrist"]), radii["forearm"]),
    ]
    if (peg := world.peg) is not None:
        top = p["tip"] + (0.0, 0.0, peg.length_m)
        links.append(("peg", along(p["tip"], top), peg.diameter_m / 2))
        links.append(("gripper", along(top, p["wrist"]), peg.gripper_diameter_m / 2))
    return links


def reach_points(world: World) -> list[tuple[str, str, np.ndarray]]:
    """The points the peg's tip must reach for each fixture (what, table, xyz m): the hole at its
    top and its bottom, the groove's corners at half its depth, the egg's top, the top of the
    obstacle (passed over)."""
    out = []
    if (h := world.hole) is not None:
        out.append(("the hole's mouth", "hole", np.array([*h.center_xy_m, h.top_z_m])))
        out.append(("the hole's bottom", "hole", np.array([*h.center_xy_m, h.top_z_m - h.depth_m])))
    if (g := world.groove) is not None:
        for name, c in zip(("entrance", "first corner", "second corner", "exit"), g.corners_xy_m):
            out.append((f"the groove's {name}", "groove", np.array([*c, g.top_z_m - g.depth_m / 2])))
    if (e := world.egg) is not None:
        out.append(("the egg's top", "egg", np.array([*e.center_xy_m, e.top_z_m])))
    if (o := world.obstacle) is not None:
        out.append(("the top of the obstacle", "obstacle", np.array([*o.center_xy_m, o.top_z_m])))
    return out


def check_layout(world: World, rest_motor_rad: Triple, fail: Fail) -> None:
    """Refuse a world whose fixtures overlap each other, overlap the arm at its resting pose, or
    hold a point the peg cannot reach: raises ``fail(table, why)``."""
    solids = fixture_solids(world)
    for i, (ta, a) in enumerate(solids):
        for tb, b in solids[i + 1 :]:
            if ta != tb and overlap(a, b):
                raise fail(tb, f"{what(b)} ({b.where()}) overlaps {what(a)} ({a.where()})")
    for table, solid in solids:
        for link, points, radius in arm_links_m(world, rest_motor_rad):
            d = solid.distance(points)
            k = int(np.argmin(d))
            if d[k] < radius:
                near = points[k]
                raise fail(
                    table,
                    f"{what(solid)} ({solid.where()}) overlaps the arm's {link} at its resting "
                    f"pose (near ({near[0]:.3f}, {near[1]:.3f}, {near[2]:.3f}) m)",
                )
    if world.table is not None:  # the arm stands on it; nothing of the arm above the base lies in it
        top = world.table.top_z_m
        for link, points, _ in arm_links_m(world, rest_motor_rad):
            k = int(np.argmin(points[:, 2]))
            if link not in ("pedestal", "waist") and points[k, 2] < top:
                near = points[k]
                raise fail(
                    "table",
                    f"the table (top at z {top:.3f} m) holds the arm's {link} at its resting pose (near "
                    f"({near[0]:.3f}, {near[1]:.3f}, {near[2]:.3f}) m)",
                )
    for name, table, point in reach_points(world):
        q, status = crs.ik_with_status(point / crs.M_PER_IN, elbow="up")
        where = f"({point[0]:.3f}, {point[1]:.3f}, {point[2]:.3f}) m"
        if int(status) != crs.IK_OK:
            raise fail(
                table, f"{name} at {where} is out of the arm's reach ({crs.IK_STATUS_TEXT[int(status)]})"
            )
        if bool(crs.outside_envelope(q)):
            raise fail(
                table,
                f"{name} at {where} is out of the arm's reach (outside the framework's safety envelope)",
            )


def corner_turns_deg(corners: np.ndarray) -> list[float]:
    """How far the Z's centre line turns at each inner corner (degrees, 0: straight on).

    >>> corner_turns_deg(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))
    [90.0, 45.0]
    """
    d = np.diff(np.asarray(corners, float), axis=0)
    u = d / np.linalg.norm(d, axis=1)[:, None]
    return [
        round(math.degrees(math.acos(float(np.clip(u[i] @ u[i + 1], -1.0, 1.0)))), 9)
        for i in range(len(u) - 1)
    ]
