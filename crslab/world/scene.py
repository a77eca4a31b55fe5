"""The MuJoCo scene of a world: the arm's own model (``models/crs_arm``) with the world's peg and
fixtures, generated from the world file as the arm is from ``params.toml``, so the two never
disagree. docs/worlds.md says why each contact parameter is what it is.

- World ``none`` is the arm's scene file itself (``models/crs_arm/scene.xml``), untouched: the
  same physics, bit for bit, as before worlds existed.
- Any other world: the arm, raised by :attr:`~crslab.world.fixtures.World.arm_raised_m` (the
  world file's frame is the lab's: the course's forward kinematics names the peg's tip, and the
  wrist is that far above it); the peg and its gripper hanging from a wrist joint at the forearm's
  end (an equality keeps them vertical: the forearm's absolute angle plus the wrist's is
  constant, as a parallel link would); collision capsules on the upper arm and the forearm (each
  touches the obstacle only, through a copy of the obstacle of its own: collision bits); and each
  fixture as a static body of boxes and cylinders (:func:`crslab.world.layout_checks.fixture_solids`;
  the hole block: a ring of staves around a 16-sided hole, a ring of inclined boxes for the
  chamfer), each with a force sensor (:data:`crslab.world.world_facts.FIXTURES`), and a site at the
  peg's tip.

>>> from crslab.world.world_file import load_world
>>> model = load_scene(load_world("contest"))
>>> model.nq, model.nu, model.joint(3).name
(4, 3, 'peg_wrist')
>>> load_scene(load_world("none")).nbody          # the arm's own scene
5
"""

from __future__ import annotations

import copy
import math
import xml.etree.ElementTree as ET

import mujoco
import numpy as np

from crslab import crs
from crslab.plant.model_files import ARM_XML, SCENE_XML
from crslab.world.fixtures import World
from crslab.world.layout_checks import fixture_solids
from crslab.world.shapes import Box, Cylinder, Shape
from crslab.world.world_facts import FIXTURES, OBSTACLE_BODIES, flatten_egg_geom

WRIST_JOINT = "peg_wrist"
"""The peg's wrist joint (world scenes only): kept at minus the forearm's absolute angle."""
PEG_BODY, PEG_TIP_SITE = "peg", "peg_tip"
HOLE_STAVES = 16
"""Sides of the polygon that stands for the round hole (its faces lie 0.2 % of the radius inside
the circle through its corners)."""
FIXTURE_SENSORS = FIXTURES
"""The bodies with a force sensor, in sensor order after the peg tip's position (C's order)."""
PEG_TYPE, FOREARM_TYPE, UPPER_ARM_TYPE = 1, 2, 4
"""Collision bits: the peg and its gripper (contype 1) touch every fixture; the forearm (2) and
the upper arm (4) only the obstacle's copy that has their bit."""
OBSTACLE_COPIES = {
    OBSTACLE_BODIES["peg"]: PEG_TYPE,
    OBSTACLE_BODIES["forearm"]: FOREARM_TYPE,
    OBSTACLE_BODIES["upper_arm"]: UPPER_ARM_TYPE,
}
"""The obstacle's three bodies, at one place, each touched by one part of the arm: each one's force
sensor says what that part presses on it (only the first is drawn)."""
ARM_COLLISION = {"upper_arm_link": UPPER_ARM_TYPE, "forearm_link": FOREARM_TYPE}
# The egg's contact is soft (R = (1 - imp) / imp * A, 2.3 times the peg's A; the arm's own inverse mass
# at the egg is ~0.2 1/kg): its force follows its spring and damper while the arm moves, not a
# nearly hard constraint's reference motion (at 0.99 that is 35 rad/s whatever the arm weighs, and
# a touch sank the peg 3.5 times deeper than an elastic egg would; docs/worlds.md, "the egg").
EGG_IMPEDANCE = 0.3


def _f(*values: float) -> str:
    return " ".join(f"{v:.10g}" for v in values)


def _body(parent: ET.Element, name: str, **attrs: str) -> ET.Element:
    return ET.SubElement(parent, "body", name=name, **attrs)


def _site(body: ET.Element, name: str, pos: tuple = (0.0, 0.0, 0.0)) -> None:
    ET.SubElement(body, "site", name=name, pos=_f(*pos), size="0.005", group="4")


class _Materials:
    """The contact attributes of each kind of fixture geom."""

    def __init__(self, world: World, egg_solref: tuple[float, float]) -> None:
        c = world.contact
        d = c.rigid_impedance
        friction = _f(c.friction, 0.005, 0.0001)
        self.rigid = {
            "priority": "1",
            "condim": "3",
            "friction": friction,
            "solref": _f(c.rigid_timeconst_s, 1.0),
            "solimp": _f(d, d, 0.001, 0.5, 2),
            "contype": "0",
            "conaffinity": str(PEG_TYPE),
        }
        self.egg = dict(
            self.rigid, solref=_f(*egg_solref), solimp=_f(EGG_IMPEDANCE, EGG_IMPEDANCE, 0.001, 0.5, 2)
        )


def _box(
    body: ET.Element,
    name: str,
    center: object,
    half: object,
    attrs: dict,
    rgba: str,
    xyaxes: object | None = None,
) -> None:
    extra = {"xyaxes": _f(*xyaxes)} if xyaxes is not None else {}
    ET.SubElement(
        body, "geom", name=name, type="box", pos=_f(*center), size=_f(*half), rgba=rgba, **extra, **attrs
    )


def _solid(body: ET.Element, shape: Shape, attrs: dict, rgba: str) -> None:
    """A geom for one of :func:`fixture_solids`' shapes (world coordinates: the body sits at 0)."""
    if isinstance(shape, Box):
        axes = (
            math.cos(shape.yaw_rad),
            math.sin(shape.yaw_rad),
            0.0,
            -math.sin(shape.yaw_rad),
            math.cos(shape.yaw_rad),
            0.0,
        )
        _box(body, shape.name, shape.center, shape.half, attrs, rgba, axes if shape.yaw_rad else None)
    else:
        assert isinstance(shape, Cylinder)
        ET.SubElement(
            body,
            "geom",
            name=shape.name,
            type="cylinder",
            pos=_f(*shape.center_xy, (shape.z_lo + shape.z_hi) / 2),
            size=_f(shape.radius, (shape.z_hi - shape.z_lo) / 2),
            rgba=rgba,
            **attrs,
        )


WOOD, STEEL, EGG, SCALE = "0.72 0.55 0.36 1", "0.55 0.57 0.6 1", "0.96 0.91 0.80 1", "0.3 0.3 0.32 1"


def _hole_block(parent: ET.Element, world: World, mat: _Materials) -> None:
    h = world.hole
    assert h is not None
    cx, cy = h.center_xy_m
    top, r, c = h.top_z_m, h.diameter_m / 2, h.chamfer_m
    bx, by = (s / 2 for s in h.block_size_xy_m)
    bottom, floor = world.floor_z_m, top - h.depth_m
    body = _body(parent, "hole", pos=_f(cx, cy, 0.0))
    _site(body, "hole_site")
    a = mat.rigid
    # the solid under the hole, and a frame around a square of half side s (past the mouth)
    _box(body, "hole_floor", (0, 0, (bottom + floor) / 2), (bx, by, (floor - bottom) / 2), a, WOOD)
    s = r + c + 0.004
    zc, zh = (floor + top) / 2, (top - floor) / 2
    _box(body, "hole_frame_px", ((bx + s) / 2, 0, zc), ((bx - s) / 2, by, zh), a, WOOD)
    _box(body, "hole_frame_nx", (-(bx + s) / 2, 0, zc), ((bx - s) / 2, by, zh), a, WOOD)
    _box(body, "hole_frame_py", (0, (by + s) / 2, zc), (s, (by - s) / 2, zh), a, WOOD)
    _box(body, "hole_frame_ny", (0, -(by + s) / 2, zc), (s, (by - s) / 2, zh), a, WOOD)
    reach = s * math.sqrt(2) + 0.002  # staves reach past the frame's inner corners
    tan = math.tan(math.pi / HOLE_STAVES)
    for i in range(HOLE_STAVES):
        th = 2 * math.pi * i / HOLE_STAVES
        radial, tangent = (math.cos(th), math.sin(th), 0.0), (-math.sin(th), math.cos(th), 0.0)
        axes = (*radial, *tangent)
        # below the chamfer: the hole's wall, its face at radius r
        t = reach - r
        z0 = top - c
        _box(
            body,
            f"hole_wall{i}",
            ((r + t / 2) * radial[0], (r + t / 2) * radial[1], (floor + z0) / 2),
            (t / 2, reach * tan * 1.02, (z0 - floor) / 2),
            a,
            WOOD,
            axes,
        )
        if c <= 0:
            continue
        # beside the chamfer, up to the top: the block's top around the mouth (radius r + c)
        t = reach - (r + c)
        _box(
            body,
            f"hole_top{i}",
            ((r + c + t / 2) * radial[0], (r + c + t / 2) * radial[1], top - c / 2),
            (t / 2, reach * tan * 1.02, c / 2),
            a,
            WOOD,
            axes,
        )
        # the chamfer: a face through (radius r, top - c) and (radius r + c, top), 45 degrees
        n = np.array([-radial[0], -radial[1], 1.0]) / math.sqrt(2)  # out of the solid: in and up
        tg = np.array(tangent)
        thick = 0.006
        centre = np.array([(r + c / 2) * radial[0], (r + c / 2) * radial[1], top - c / 2]) - n * thick / 2
        _box(
            body,
            f"hole_chamfer{i}",
            centre,
            (thick / 2, (r + c) * tan * 1.02, c / math.sqrt(2)),
            a,
            WOOD,
            (*n, *tg),
        )


def _fixture_bodies(worldbody: ET.Element, world: World, mat: _Materials) -> None:
    """The obstacle (three copies), the groove plate and its stands, the egg, the scale and its stand,
    from :func:`fixture_solids`."""
    solids = fixture_solids(world)
    if (o := world.obstacle) is not None:
        post = next(s for t, s in solids if t == "obstacle")
        top = (*o.center_xy_m, o.top_z_m)
        for name, bit in OBSTACLE_COPIES.items():
            body = _body(worldbody, name)
            _site(body, f"{name}_site", top)
            drawn = name == OBSTACLE_BODIES["peg"]
            _solid(
                body,
                Box(post.center, post.half, 0.0, name if drawn else f"{name}_copy"),  # type: ignore[union-attr]
                dict(mat.rigid, conaffinity=str(bit), group="0" if drawn else "3"),
                "0.75 0.25 0.2 1" if drawn else "0 0 0 0",
            )
    if (g := world.groove) is not None:
        body = _body(worldbody, "groove")
        _site(body, "groove_site", (*g.corners_xy_m[0], g.top_z_m))
        for table, shape in solids:
            if table == "groove":
                _solid(body, shape, mat.rigid, WOOD if "stand" in shape.name else STEEL)
    if (e := world.egg) is not None:
        egg = _body(worldbody, "egg", pos=_f(*e.center_xy_m, 0.0))
        _site(egg, "egg_site")
        ET.SubElement(
            egg,
            "geom",
            name="egg",
            type="ellipsoid",
            pos=_f(0, 0, e.top_z_m - e.height_m / 2),
            size=_f(e.diameter_m / 2, e.diameter_m / 2, e.height_m / 2),
            rgba=EGG,
            **mat.egg,
        )
        scale = _body(worldbody, "scale")
        _site(scale, "scale_site", (*e.center_xy_m, e.scale_top_z_m))
        stands = None
        for table, shape in solids:
            if table == "egg" and shape.name == "scale":
                _solid(scale, shape, mat.rigid, SCALE)
            elif table == "egg" and shape.name == "scale_stand":
                stands = stands if stands is not None else _body(worldbody, "stands")
                _solid(stands, shape, mat.rigid, WOOD)


def _peg(forearm: ET.Element, world: World) -> None:
    """The peg and its gripper on the wrist at the forearm's end, in the forearm's frame: at DH zero
    (the frame the wrist's angle 0 is defined in) their axis is the world's vertical, the tip
    ``wrist_above_tip_m`` below the wrist."""
    p = world.peg
    assert p is not None
    ee = np.array([crs.FOREARM_IN * crs.M_PER_IN, 0.0, 0.0])
    rot = crs.fk_pose_dh(np.zeros(3))[:3, :3]  # the forearm's frame at DH zero, in the world
    up = rot.T @ np.array([0.0, 0.0, 1.0])
    tip = -up * p.wrist_above_tip_m
    r, length, rg = p.diameter_m / 2, p.length_m, p.gripper_diameter_m / 2
    body = _body(forearm, PEG_BODY, pos=_f(*ee))
    ET.SubElement(
        body,
        "joint",
        name=WRIST_JOINT,
        type="hinge",
        axis="0 0 1",
        limited="false",
        frictionloss="0",
        armature="0.001",
    )
    # a solid cylinder (the peg; the gripper's mass is the forearm's): inertia about its centre,
    # axis along "up"
    axial, across = p.mass_kg * r * r / 2, p.mass_kg * (3 * r * r + length * length) / 12
    com = tip + up * length / 2
    ET.SubElement(
        body,
        "inertial",
        pos=_f(*com),
        mass=_f(p.mass_kg),
        fullinertia=_f(
            *(across * np.eye(3) + (axial - across) * np.outer(up, up))[
                [0, 1, 2, 0, 0, 1], [0, 1, 2, 1, 2, 2]
            ]
        ),
    )
    collides = {"contype": str(PEG_TYPE), "conaffinity": "0", "group": "1"}
    ET.SubElement(
        body,
        "geom",
        name="peg",
        type="capsule",
        fromto=_f(*(tip + up * r), *(tip + up * (length - r))),
        size=_f(r),
        rgba=STEEL,
        **collides,
    )
    # the gripper: from the peg's top up to the wrist (its lower end's round sits on the peg's top)
    ET.SubElement(
        body,
        "geom",
        name="gripper",
        type="capsule",
        fromto=_f(*(tip + up * (length + rg)), 0.0, 0.0, 0.0),
        size=_f(rg),
        rgba="0.25 0.25 0.28 1",
        **collides,
    )
    ET.SubElement(body, "site", name=PEG_TIP_SITE, pos=_f(*tip), size="0.003", group="4")


def _arm_collision(root: ET.Element) -> None:
    """Collision capsules on the upper arm and the forearm, as their visual capsules: each touches its
    own copy of the obstacle only (collision bits), never the fixtures the peg works in."""
    for body in root.iter("body"):
        for g in list(body.findall("geom")):
            if (bit := ARM_COLLISION.get(g.get("name", ""))) is not None:
                body.append(
                    ET.Element(
                        "geom",
                        name=g.get("name") + "_collision",
                        type="capsule",
                        fromto=g.get("fromto"),
                        size=g.get("size"),
                        group="3",
                        contype=str(bit),
                        conaffinity="0",
                        rgba="0 0 0 0",
                    )
                )


def _raise_arm(root: ET.Element, raised_m: float) -> None:
    """Stand the arm ``raised_m`` higher: its pedestal and its waist (and everything on it)."""
    worldbody = root.find("worldbody")
    assert worldbody is not None
    for child in worldbody:
        if child.tag == "geom" and child.get("name") == "pedestal":
            a = [float(v) for v in (child.get("fromto") or "").split()]
            child.set("fromto", _f(a[0], a[1], a[2] + raised_m, a[3], a[4], a[5] + raised_m))
        elif child.tag == "body" and child.get("name") == "waist":
            pos = [float(v) for v in child.get("pos", "0 0 0").split()]
            child.set("pos", _f(pos[0], pos[1], pos[2] + raised_m))


def _world_root(world: World, egg_solref: tuple[float, float]) -> ET.Element:
    arm = ET.parse(ARM_XML).getroot()
    scene = ET.parse(SCENE_XML).getroot()
    root = ET.Element("mujoco", model=f"crs_arm in world {world.name}")
    for child in arm:
        root.append(copy.deepcopy(child))
    _raise_arm(root, world.arm_raised_m)
    worldbody = root.find("worldbody")
    assert worldbody is not None
    for child in scene:
        if child.tag == "include":
            continue
        if child.tag == "worldbody":
            worldbody.extend(copy.deepcopy(list(child)))
        elif child.tag == "option":
            option = copy.deepcopy(child)
            option.set("cone", "elliptic")  # a contact's normal force is one row of its own
            for flag in option.iter("flag"):  # the arm alone skips collisions: its fixtures need them
                flag.attrib.pop("contact", None)
            root.append(option)
        else:
            root.append(copy.deepcopy(child))
    mat = _Materials(world, egg_solref)
    if world.peg is not None:
        forearm = next(b for b in root.iter("body") if b.get("name") == "forearm")
        _peg(forearm, world)
        tendon = root.find("tendon")
        assert tendon is not None
        pitch = ET.SubElement(tendon, "fixed", name="peg_pitch")
        for j in ("j2", "j3", WRIST_JOINT):
            ET.SubElement(pitch, "joint", joint=j, coef="1")
        equality = ET.SubElement(root, "equality")
        ET.SubElement(
            equality,
            "tendon",
            name="peg_vertical",
            tendon1="peg_pitch",
            solref="0.004 1",
            solimp="0.99 0.99 0.001 0.5 2",
        )
        for key in root.iter("key"):
            q = [float(v) for v in key.get("qpos", "").split()]
            key.set("qpos", _f(*q, -(q[1] + q[2])))
    _arm_collision(root)
    if (t := world.table) is not None:
        body = _body(worldbody, "table")
        _site(body, "table_site")
        _box(
            body,
            "table",
            (0, 0, t.top_z_m - t.size_m[2] / 2),
            np.asarray(t.size_m) / 2,
            mat.rigid,
            "0.45 0.42 0.38 1",
        )
    if world.hole is not None:
        _hole_block(worldbody, world, mat)
    _fixture_bodies(worldbody, world, mat)
    sensor = ET.SubElement(root, "sensor")
    if world.peg is not None:
        ET.SubElement(sensor, "framepos", name="peg_tip", objtype="site", objname=PEG_TIP_SITE)
    for name in FIXTURE_SENSORS:
        if worldbody.find(f"body[@name='{name}']") is not None:
            ET.SubElement(sensor, "force", name=f"{name}_force", site=f"{name}_site")
    ET.indent(root)
    return root


def egg_solref(world: World, peg_invweight: float, arm_mass_kg: float) -> tuple[float, float]:
    """The egg contact's ``solref`` in MuJoCo's direct form ``(-stiffness, -damping)`` that makes it a
    spring of ``world.egg.stiffness_n_per_m`` N/m (shell and scale in series) against the peg, with
    a damper ``egg_damping_ratio`` of critical for the arm pressing it (``arm_mass_kg`` at the tip,
    vertically, on the egg's top; docs/worlds.md derives it).

    MuJoCo's contact force is ``f = (a_ref - a0) / (A_arm + R)`` with the reference acceleration
    ``a_ref = -B v - K imp r`` (r the penetration, v its speed), ``R = (1 - imp) / imp * A``
    (``A``: the contact's approximate inverse mass, here the peg's translational inverse weight)
    and, for the direct form, ``K = stiffness / imp^2``, ``B = damping / imp``. At rest
    (``a0 = -A_arm f``) that is ``R f = K imp r``: r = f (1 - imp) A / stiffness, so the stiffness
    in MuJoCo's units is ``k * (1 - imp) * A``; moving, with R well above the arm's A_arm, the
    damper is ``damping / ((1 - imp) A)`` N s/m, so ``damping = c * (1 - imp) * A``.

    >>> from crslab.world.world_file import load_world
    >>> s, b = egg_solref(load_world("contest"), 1.65, 4.9)
    >>> round(-s), round(-b)
    (16500, 122)
    """
    e = world.egg
    assert e is not None
    d = EGG_IMPEDANCE
    stiffness = e.stiffness_n_per_m * (1 - d) * peg_invweight
    c = 2 * world.contact.egg_damping_ratio * math.sqrt(e.stiffness_n_per_m * arm_mass_kg)  # N s/m
    return (-stiffness, -c * (1 - d) * peg_invweight)


def arm_mass_at_kg(model: mujoco.MjModel, xyz_m: object) -> float:
    """The arm's mass at the peg's tip, vertically, with the tip at ``xyz_m`` (m): ``1 / (J M^-1
    J^T)_zz`` over the arm's three joints, the peg's wrist following them.

    >>> from crslab.world.world_file import load_world
    >>> round(arm_mass_at_kg(load_scene(load_world("contest")), (0.226, 0.184, 0.2975)), 1)
    5.0
    """
    data = mujoco.MjData(model)
    set_arm_pose(model, data, crs.ik_dh(np.asarray(xyz_m, dtype=float) / crs.M_PER_IN))
    mujoco.mj_forward(model, data)
    jac = np.zeros((3, model.nv))
    mujoco.mj_jacSite(model, data, jac, None, model.site(PEG_TIP_SITE).id)
    inertia = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, inertia)
    follow = np.zeros((model.nv, 3))
    follow[:3, :3] = np.eye(3)
    follow[model.jnt_dofadr[model.joint(WRIST_JOINT).id]] = (0.0, -1.0, -1.0)
    jac, inertia = jac @ follow, follow.T @ inertia @ follow
    return 1.0 / float((jac @ np.linalg.solve(inertia, jac.T))[2, 2])


def scene_xml(world: World) -> str:
    """The MJCF text of ``world``'s scene (``none``: the arm's own scene file, as it is)."""
    if world.is_free_air:
        return SCENE_XML.read_text()
    solref = (-1.0, -1.0)
    if world.egg is not None:  # the peg's inverse weight and the arm's mass from the compiled scene
        first = mujoco.MjModel.from_xml_string(ET.tostring(_world_root(world, solref), encoding="unicode"))
        on_top = (*world.egg.center_xy_m, world.egg.top_z_m)
        solref = egg_solref(
            world, float(first.body_invweight0[first.body(PEG_BODY).id][0]), arm_mass_at_kg(first, on_top)
        )
    return ET.tostring(_world_root(world, solref), encoding="unicode")


def load_scene(world: World) -> mujoco.MjModel:
    """The compiled scene of ``world`` (``none``: exactly :func:`crslab.plant.model.load_model`'s)."""
    if world.is_free_air:
        return mujoco.MjModel.from_xml_path(str(SCENE_XML))
    return mujoco.MjModel.from_xml_string(scene_xml(world))


def set_arm_pose(model: mujoco.MjModel, data: mujoco.MjData, dh_rad: object) -> None:
    """Put the arm at DH angles ``dh_rad`` (rad), the peg's wrist where its equality holds it."""
    q = np.asarray(dh_rad, dtype=float)
    data.qpos[:3] = q
    if model.nq > 3:
        data.qpos[model.jnt_qposadr[model.joint(WRIST_JOINT).id]] = -(q[1] + q[2])


def flatten_egg(model: mujoco.MjModel) -> None:
    """Draw the egg broken, as the board does when it breaks (csrc/plant/world.c): flat on the scale,
    no longer colliding. Doing it twice changes nothing more."""
    egg = model.geom("egg").id
    if model.geom_conaffinity[egg] == 0:
        return
    flatten_egg_geom(model.geom_size[egg], model.geom_pos[egg])
    model.geom_contype[egg] = model.geom_conaffinity[egg] = 0
