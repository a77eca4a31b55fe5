"""The world's contacts do what their materials say (docs/worlds.md), and every quantity the board's
C world computes (csrc/plant/world.c) is what an independent computation gives, derived, not
recorded.

The scene is the contest world's own (crslab.world.scene), stepped by MuJoCo directly with the
arm's joint friction and gravity taken out, so that the only forces are the ones each test
applies and the contact's: a known force on a rigid block and on the egg stops the peg at the
penetration the contact's solref/solimp give; a soft x-y impedance slides the peg into the
chamfered hole from 7 mm off while a stiff one jams on the chamfer (and without the chamfer the
soft one jams too). The C world's row on those states is checked against MuJoCo's own contact
forces (mj_contactForce, summed per fixture and per arm part: not the sensors C reads) and
against the forces the test applied: each fixture's force, the obstacle's by part, the groove's
side force (across its segment, never along it), the peg's depth, the scale's grams (also equal
to the force the motors' torques give through the course's Jacobian at rest, J^T F = tau). The
board's path: a hand pressing past the breaking force breaks the egg for the rest of the run, the
scale says so, and what broke it is the press; a fall and a side hit are told apart.
"""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest
from crslab._core import ffi, lib

from crslab import crs
from crslab._bindings import compiled_board
from crslab.worker.board import world_config
from crslab.world import load_world, world_file
from crslab.world.scene import PEG_BODY, PEG_TIP_SITE, load_scene, set_arm_pose
from crslab.world.world_facts import EGG_FALL_M_S, SCALE_GRAVITY_M_S2, split_world_row

CONTEST = load_world("contest")
CONTEST_FILE = world_file("contest")[0]


def free_scene(world=CONTEST):
    """The world's scene with nothing but the forces a test applies: no gravity, no joint friction,
    no actuator bias."""
    m = load_scene(world)
    m.opt.gravity[:] = 0.0
    m.dof_frictionloss[:] = 0.0
    m.tendon_frictionloss[:] = 0.0
    m.actuator_biasprm[:] = 0.0
    d = mujoco.MjData(m)
    return m, d


def place_tip(m, d, xyz_m):
    set_arm_pose(m, d, crs.ik_dh(np.asarray(xyz_m) / crs.M_PER_IN))
    mujoco.mj_forward(m, d)


def press(m, d, force_n, steps=3000):
    """Push the peg's tip with ``force_n`` (world frame) until it rests; returns the contacts."""
    peg, tip = m.body(PEG_BODY).id, m.site(PEG_TIP_SITE).id
    for _ in range(steps):
        d.qfrc_applied[:] = 0.0
        mujoco.mj_applyFT(
            m, d, np.asarray(force_n, float), np.zeros(3), d.site_xpos[tip].copy(), peg, d.qfrc_applied
        )
        mujoco.mj_step(m, d)
    assert np.abs(d.qvel).max() < 1e-6  # at rest
    return [d.contact[i] for i in range(d.ncon)]


def test_a_known_force_on_the_rigid_block_stops_the_peg_at_the_penetration_its_solref_gives():
    m, d = free_scene()
    h = CONTEST.hole
    place_tip(m, d, (h.center_xy_m[0] + 0.025, h.center_xy_m[1], h.top_z_m + 0.0005))  # on the block's top
    force = 10.0
    (c,) = press(m, d, (0.0, 0.0, -force))
    assert m.geom(c.geom2 if m.geom(c.geom1).name == "peg" else c.geom1).name.startswith("hole_")
    # MuJoCo at rest: R f = K imp r (the reference acceleration), R = (1 - imp) / imp * A, and for
    # solref (timeconst, dampratio) K = 1 / (imp^2 timeconst^2 dampratio^2): r = (1 - imp) A tc^2 dr^2 f
    g = m.geom("hole_frame_px")
    timeconst, dampratio = g.solref
    imp = g.solimp[0]
    assert g.solimp[1] == imp  # a constant impedance: the spring is linear
    inverse_mass = m.body_invweight0[m.body(PEG_BODY).id][0]  # A: MuJoCo's approximation for the peg
    expected = (1 - imp) * inverse_mass * timeconst**2 * dampratio**2 * force
    assert -c.dist == pytest.approx(expected, rel=0.01)
    assert 1e-7 < expected < 5e-6  # rigid: a few micrometres under 10 N (~1e7 N/m)
    f = np.zeros(6)
    mujoco.mj_contactForce(m, d, 0, f)
    assert f[0] == pytest.approx(force, rel=1e-6)  # the normal force carries all of it


def test_the_egg_is_a_spring_of_the_worlds_stiffness():
    m, d = free_scene()
    e = CONTEST.egg
    place_tip(m, d, (*e.center_xy_m, e.top_z_m + 0.0003))
    for force in (5.0, 10.0):
        (c,) = press(m, d, (0.0, 0.0, -force))
        assert m.geom(c.geom2).name == "egg" or m.geom(c.geom1).name == "egg"
        assert -c.dist == pytest.approx(force / e.stiffness_n_per_m, rel=0.02), force  # r = F / k


def test_a_touch_on_the_egg_sinks_the_peg_as_far_as_an_elastic_egg_under_the_arm_would():
    """The arm comes down on the egg at 15 mm/s, nothing else pushing: the peg sinks as a mass-
    spring-damper does, the arm's mass at the tip (from MuJoCo's mass matrix and the tip's Jacobian)
    on the egg's spring k and its damper c = 2 ratio sqrt(k m) (docs/worlds.md): as deep as
    ``x = v / w_d exp(-zeta w t) sin(w_d t)`` goes, with the force k x + c x' at its largest."""
    m, d = free_scene()
    e = CONTEST.egg
    place_tip(m, d, (*e.center_xy_m, e.top_z_m + 0.0001))
    site = m.site(PEG_TIP_SITE).id
    jac = np.zeros((3, m.nv))
    mujoco.mj_jacSite(m, d, jac, None, site)
    inertia = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, inertia)
    # the arm's three joints; the peg's wrist follows minus the forearm's angle (j2 + j3)
    arm = np.array([[1.0, 0, 0], [0, 1, 0], [0, 0, 1], [0, -1, -1]])
    jac, inertia = jac @ arm, arm.T @ inertia @ arm
    mass = 1.0 / (jac @ np.linalg.solve(inertia, jac.T))[2, 2]  # kg, at the tip, vertically
    assert 3.0 < mass < 7.0  # mostly the rotors (models/crs_arm/README.md)
    v = 0.015
    d.qvel[:] = arm @ np.linalg.solve(jac, [0.0, 0.0, -v])
    k = e.stiffness_n_per_m
    c = 2 * CONTEST.contact.egg_damping_ratio * np.sqrt(k * mass)  # its ratio of critical for the arm
    w = np.sqrt(k / mass)
    zeta = c / (2 * np.sqrt(k * mass))
    wd = w * np.sqrt(1 - zeta**2)
    ts = np.linspace(0.0, np.pi / wd, 10001)  # the first half-period: the peg in the egg
    x = v / wd * np.exp(-zeta * w * ts) * np.sin(wd * ts)
    x_dot = v * np.exp(-zeta * w * ts) * (np.cos(wd * ts) - zeta * w / wd * np.sin(wd * ts))
    sunk, force = [], []
    for _ in range(200):
        mujoco.mj_step(m, d)
        sunk.append(e.top_z_m - d.site_xpos[site][2])
        f = np.zeros(6)
        force.append(sum(mujoco.mj_contactForce(m, d, i, f) or f[0] for i in range(d.ncon)))
    assert max(sunk) == pytest.approx(x.max(), rel=0.1)  # 0.1 mm, not 3.5 times as deep
    assert max(force) == pytest.approx((k * x + c * x_dot).max(), rel=0.1)


def test_a_soft_xy_impedance_slides_into_the_chamfered_hole_a_stiff_one_jams():
    def insert(kxy, world=CONTEST, off=0.007):
        """Task-space impedance at the peg's tip (tau = J^T (K (xd - x) - D v)), aiming 4 cm below the
        hole's top from ``off`` beside its axis; returns the depth reached below the top (m)."""
        m, d = free_scene(world)
        h = world.hole
        start = np.array([h.center_xy_m[0] + off, h.center_xy_m[1], h.top_z_m + 0.003])
        place_tip(m, d, start)
        stiffness = np.array([kxy, kxy, 300.0])
        damping = 2 * np.sqrt(stiffness * 5.0)  # about critical for the arm's ~5 kg at the tip
        target = start - (0.0, 0.0, 0.04)
        tip, jac = m.site(PEG_TIP_SITE).id, np.zeros((3, m.nv))
        for _ in range(2000):
            mujoco.mj_jacSite(m, d, jac, None, tip)
            force = stiffness * (target - d.site_xpos[tip]) - damping * (jac @ d.qvel)
            d.qfrc_applied[:] = jac.T @ force
            mujoco.mj_step(m, d)
        return h.top_z_m - d.site_xpos[tip][2]

    soft, stiff = 30.0, 20000.0  # N/m across the hole
    assert insert(soft) > 0.03  # in, most of the 4 cm asked
    assert insert(stiff) < CONTEST.hole.chamfer_m  # stuck on the chamfer
    flat = dataclasses.replace(CONTEST, hole=dataclasses.replace(CONTEST.hole, chamfer_m=0.0))
    assert insert(soft, flat) < 0.001  # no chamfer: the soft peg sits on the edge too


def world_row(m, d, world=CONTEST, state=None):
    """The board's C (crs_world_update) on this state's sensors: the scope row, by name. ``state``: a
    ``crs_world`` to go on updating (its latches and the tip's last place), else a new one."""
    if state is None:
        w = ffi.new("crs_world *")
        config, keep = world_config(compiled_board(), m, d, world)
        lib.crs_world_attach(w, config)
        state = (w, keep)  # what the world points at stays alive with it
    w = state[0]
    lib.crs_world_update(w, 0)
    row = split_world_row([w.state.row[i] for i in range(lib.CRS_WORLD_ROW)])
    return {k: (v.tolist() if len(v) == 3 else float(v[0])) for k, v in row.items()}, state


def pressed_on(m, d, body):
    """The force (N, world frame) the arm presses on ``body`` by MuJoCo's contacts (mj_contactForce),
    not its sensors: the sum over every contact one of whose geoms is the body's."""
    fixture = m.body(body).id
    total = np.zeros(3)
    for i in range(d.ncon):
        c = d.contact[i]
        f = np.zeros(6)
        mujoco.mj_contactForce(m, d, i, f)
        on_geom2 = c.frame.reshape(3, 3).T @ f[:3]  # the normal (frame's x) points from geom1 to geom2
        if m.geom_bodyid[c.geom2] == fixture:
            total += on_geom2
        elif m.geom_bodyid[c.geom1] == fixture:
            total -= on_geom2
    return total


def test_the_scale_reads_the_eggs_force_as_the_motors_torques_give_it_through_the_course_jacobian():
    m, d = free_scene()
    e = CONTEST.egg
    place_tip(m, d, (*e.center_xy_m, e.top_z_m + 0.0003))
    motor = crs.dh_to_motor(d.qpos[:3])
    jacobian_m = crs.jacobian(motor) * crs.M_PER_IN  # d(xyz m)/d(motor angles rad): the course's
    pressing = np.array([0.0, 0.0, -7.0])  # N down: about 714 g, in the contest's band
    gear = m.actuator_gear[:, 0]
    d.ctrl[:] = jacobian_m.T @ pressing / gear  # motor torques (command units) for that force
    for _ in range(3000):
        mujoco.mj_step(m, d)
    assert np.abs(d.qvel).max() < 1e-6
    # 1: the contact's force, MuJoCo's own
    f = np.zeros(6)
    names = [(m.geom(d.contact[k].geom1).name, m.geom(d.contact[k].geom2).name) for k in range(d.ncon)]
    (i,) = [k for k, pair in enumerate(names) if "egg" in pair]
    mujoco.mj_contactForce(m, d, i, f)
    normal = f[0]
    # 2: at rest the motors' torques balance the contact: J^T F = tau, F = J^-T tau (the force on the egg)
    tau = d.actuator_force * gear  # N.m about each motor angle
    at_rest = crs.jacobian(crs.dh_to_motor(d.qpos[:3])) * crs.M_PER_IN  # where the peg came to rest
    from_torques = np.linalg.solve(at_rest.T, tau)
    # 3: the scale, as the board computes it
    row, _ = world_row(m, d)
    assert row["egg_force"] == pytest.approx(np.linalg.norm(f[:3]), rel=1e-6)
    assert row["egg_force"] == pytest.approx(np.linalg.norm(from_torques), rel=1e-4)
    assert row["scale_g"] == pytest.approx(-from_torques[2] / SCALE_GRAVITY_M_S2 * 1000, rel=1e-4)
    assert row["scale_g"] == pytest.approx(normal / SCALE_GRAVITY_M_S2 * 1000, rel=0.01)  # pressed from above
    assert row["scale_g"] == pytest.approx(7.0 / SCALE_GRAVITY_M_S2 * 1000, rel=0.01)
    assert np.allclose(row["peg_tip"], d.site_xpos[m.site(PEG_TIP_SITE).id])
    assert np.allclose(row["egg_force_xyz"], pressed_on(m, d, "egg"), rtol=1e-6, atol=1e-9)
    assert row["egg_broken"] == 0.0


def test_past_the_breaking_force_the_egg_is_broken_for_the_rest_of_the_run_and_the_scale_says_so(tmp_path):
    from crslab.run.api import simulate

    e = CONTEST.egg
    x, y = (v / crs.M_PER_IN for v in e.center_xy_m)
    scenario = tmp_path / "crush.toml"
    above, into = (e.top_z_m + 0.02) / crs.M_PER_IN, (e.top_z_m - 0.004) / crs.M_PER_IN
    scenario.write_text(
        "end = 5.0\n"
        f'[[event]]\nat = 0.2\nkind = "hand"\nxyz_in = [{x:.5f}, {y:.5f}, {above:.5f}]\nduration = 1.5\n'
        f'[[event]]\nat = 2.0\nkind = "hand"\nxyz_in = [{x:.5f}, {y:.5f}, {into:.5f}]\nduration = 1.5\n'
        '[[event]]\nat = 4.9\nkind = "expect"\negg_broken = true\nscale_g = [0, 0]\n'
    )
    r = simulate(None, str(scenario), world="contest", log=True)
    assert r.ok, r.diagnosis()
    force, grams, broken = (r.log[k][:, 0] for k in ("egg_force", "scale_g", "egg_broken"))
    first = int(np.argmax(broken > 0))
    assert broken[first:].all() and not broken[:first].any()  # latched
    assert force[first] > e.breaking_force_n >= force[:first].max()  # it broke on the tick it passed
    # the scale shows the downward part of the force: all of it pressed from straight above
    down_n = grams[first - 1] * SCALE_GRAVITY_M_S2 / 1000
    assert 0.5 * force[first - 1] < down_n <= force[first - 1] * (1 + 1e-12)
    assert (force[first + 1 :] == 0).all() and (grams[first + 1 :] == 0).all()  # nothing holds the peg up


def test_the_peg_fits_along_the_whole_groove_the_plate_at_half_the_width_from_the_centre_line():
    """No box of the groove plate's top (in the compiled scene) reaches into the channel: every one
    is at least half the groove's width from the Z's centre line, and along the legs and at the
    capped ends the nearest is exactly that far; a peg following the line touches nothing."""
    world = load_world("contest")
    model = load_scene(world)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    g = world.groove
    corners = np.asarray(g.corners_xy_m)
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, i) or "" for i in range(model.ngeom)]
    tops = [i for i, name in enumerate(names) if name.startswith("groove_top")]
    assert len(tops) >= 8 * 3  # every edge of the channel has its layers

    def nearest_top_m(point):
        out = []
        for i in tops:
            rot = data.geom_xmat[i].reshape(3, 3)[:2, :2]
            local = np.abs(rot.T @ (point - data.geom_xpos[i][:2])) - model.geom_size[i][:2]
            out.append(float(np.linalg.norm(np.maximum(local, 0.0))))
        return min(out)

    line = [
        (i, t, corners[i] + t * (corners[i + 1] - corners[i]))
        for i in range(3)
        for t in np.linspace(0, 1, 301)
    ]
    distances = [nearest_top_m(p) for _, _, p in line]
    assert min(distances) >= g.width_m / 2 - 1e-9
    mids = [d for (_, t, _), d in zip(line, distances) if 0.4 <= t <= 0.6]
    assert mids == pytest.approx([g.width_m / 2] * len(mids), abs=1e-9)
    assert nearest_top_m(corners[0]) == pytest.approx(g.width_m / 2, abs=1e-9)
    assert nearest_top_m(corners[-1]) == pytest.approx(g.width_m / 2, abs=1e-9)


def rest_at(m, d, place, force_n, body=PEG_BODY, at=None, steps=3000):
    """Put the tip at ``place``, then push ``body`` with ``force_n`` (world frame) at ``at`` (default:
    the peg's tip) until everything rests; returns the C world's row there."""
    place_tip(m, d, place)
    point = None if at is None else np.asarray(at, float)
    for _ in range(steps):
        d.qfrc_applied[:] = 0.0
        where = d.site_xpos[m.site(PEG_TIP_SITE).id].copy() if point is None else point
        mujoco.mj_applyFT(
            m, d, np.asarray(force_n, float), np.zeros(3), where, m.body(body).id, d.qfrc_applied
        )
        mujoco.mj_step(m, d)
    assert np.abs(d.qvel).max() < 1e-5
    return world_row(m, d)[0]


@pytest.mark.parametrize(
    "fixture, place, push",
    [
        (
            "hole",
            lambda w: (w.hole.center_xy_m[0] + 0.025, w.hole.center_xy_m[1], w.hole.top_z_m + 0.0005),
            (0, 0, -6.0),
        ),
        ("groove", lambda w: (*w.groove.corners_xy_m[1], w.groove.floor_z_m + 0.0005), (0, 0, -4.0)),
        ("obstacle", lambda w: (*w.obstacle.center_xy_m, w.obstacle.top_z_m + 0.0005), (0, 0, -5.0)),
        (
            "scale",
            lambda w: (w.egg.center_xy_m[0] + 0.032, w.egg.center_xy_m[1], w.egg.scale_top_z_m + 0.0005),
            (0, 0, -3.0),
        ),
    ],
)
def test_each_fixtures_force_is_the_force_the_arm_presses_on_it(fixture, place, push):
    """A known force pressing the peg on each fixture: at rest the C row's force on that fixture is
    the pushing force and MuJoCo's contact force on its body; every other fixture feels nothing."""
    m, d = free_scene()
    row = rest_at(m, d, place(CONTEST), push)
    column = {"scale": "scale_g", "obstacle": "obstacle_peg_force"}.get(fixture, f"{fixture}_force")
    by_contacts = pressed_on(m, d, fixture)
    assert by_contacts == pytest.approx(np.asarray(push, float), abs=1e-6)
    if fixture == "scale":  # grams: the platform pressed beside the egg counts on the scale, not the egg
        assert row["scale_g"] == pytest.approx(-push[2] / SCALE_GRAVITY_M_S2 * 1000, rel=1e-6)
        assert row["egg_force"] == 0.0
    else:
        assert row[column] == pytest.approx(np.linalg.norm(push), rel=1e-6)
    others = {
        "hole_force",
        "groove_force",
        "obstacle_force",
        "obstacle_peg_force",
        "egg_force",
        "table_force",
    }
    others -= {column, "obstacle_force" if fixture == "obstacle" else ""}
    assert all(row[k] == 0.0 for k in others), row
    if fixture == "obstacle":  # the peg alone: the whole force on the obstacle is the peg's
        assert row["obstacle_force"] == row["obstacle_peg_force"]
        assert row["obstacle_forearm_force"] == row["obstacle_upper_arm_force"] == 0.0


def test_the_obstacle_says_which_part_of_the_arm_presses_it(tmp_path):
    """A post under the forearm, the forearm pushed down onto it: the whole force is the forearm's
    (MuJoCo's contacts on the obstacle's forearm copy, and the push), none the peg's."""
    from crslab.world.world_file import parse_world

    peg = CONTEST_FILE.read_text().split("[peg]")[1].split("[hole]")[0]
    place = (0.35, 0.0, 0.45)  # the tip there: the forearm reaches back over x 0.30 from its wrist
    m, d = free_scene(load_world("contest"))
    place_tip(m, d, place)
    g, r = d.geom("forearm_link_collision"), m.geom("forearm_link_collision").size[0]
    axis = g.xmat.reshape(3, 3)[:, 2]
    under = g.xpos[2] + (0.30 - g.xpos[0]) / axis[0] * axis[2] - r  # the forearm's bottom over x 0.30
    world = parse_world(
        f"[peg]{peg}[obstacle]\ncenter_xy_m = [0.30, 0.0]\ntop_z_m = {under - 0.001:.4f}\n"
        "size_xy_m = [0.03, 0.03]\n",
        "under_forearm.toml",
        rest_motor_rad=(np.pi / 2, -0.42, 0.24),
    )
    m, d = free_scene(world)
    place_tip(m, d, place)
    forearm = m.body("forearm").id
    seen = 0
    for _ in range(300):  # the forearm pushed down at its middle: it presses the post, the arm turning
        d.qfrc_applied[:] = 0.0
        mujoco.mj_applyFT(
            m, d, np.array([0.0, 0.0, -8.0]), np.zeros(3), d.xipos[forearm].copy(), forearm, d.qfrc_applied
        )
        mujoco.mj_step(m, d)
        row, _ = world_row(m, d, world)
        by_contacts = pressed_on(m, d, "obstacle_forearm")
        assert row["obstacle_forearm_force"] == pytest.approx(
            np.linalg.norm(by_contacts), rel=1e-9, abs=1e-12
        )
        assert row["obstacle_peg_force"] == row["obstacle_upper_arm_force"] == 0.0
        assert row["obstacle_force"] == pytest.approx(row["obstacle_forearm_force"], rel=1e-12)
        seen += row["obstacle_forearm_force"] > 1.0
    assert seen >= 20  # it pressed the post (harder than 1 N) for a while before the arm turned off it
    assert pressed_on(m, d, "obstacle") == pytest.approx(np.zeros(3))  # nothing of the peg's


def test_the_grooves_side_force_is_across_its_segment_never_along_it():
    """The peg pushed against a wall of the groove's second segment (along -x from corner 1 to
    corner 2): 5 N across it and 1.5 N along it (held by the wall's friction, 0.4 x 5 = 2 N). The
    row's side force is the 5 N across, by the push and by MuJoCo's contact forces on the plate
    resolved across the segment; the 1.5 N along it is not in it (an axis swapped in world.c
    reports the along part, or 5.2 N)."""
    m, d = free_scene()
    g = CONTEST.groove
    (x1, y1), (x2, y2) = g.corners_xy_m[1], g.corners_xy_m[2]
    u = np.array([x2 - x1, y2 - y1]) / np.hypot(x2 - x1, y2 - y1)  # along the segment
    n = np.array([-u[1], u[0]])  # across it (its left)
    middle = (np.array([x1, y1]) + np.array([x2, y2])) / 2
    place = (*(middle + n * 0.002), g.floor_z_m + 0.005)  # in the channel, 5 mm over its floor
    push = np.array([*(5.0 * n + 1.5 * u), 0.0])
    row = rest_at(m, d, place, push)
    by_contacts = pressed_on(m, d, "groove")
    # the wall takes the push (where it touches the peg, a little above the tip the push is at)
    assert by_contacts == pytest.approx(push, rel=0.01, abs=0.01)
    across = abs(by_contacts[:2] @ n)
    assert row["groove_side_force"] == pytest.approx(across, rel=1e-9) == pytest.approx(5.0, rel=0.01)
    assert row["groove_force"] == pytest.approx(np.linalg.norm(by_contacts), rel=1e-9)
    assert abs(by_contacts[:2] @ u) == pytest.approx(
        1.5, rel=0.01
    )  # along the segment: not in the side force
    assert row["groove_segment"] == 1.0
    tip = np.asarray(row["peg_tip"])
    # the peg rests against the left wall: its tip half the width less the peg's radius off the line
    assert row["groove_offset"] == pytest.approx(g.width_m / 2 - CONTEST.peg.diameter_m / 2, abs=2e-4)
    seg0 = np.hypot(*np.subtract(g.corners_xy_m[1], g.corners_xy_m[0]))
    assert row["groove_along"] == pytest.approx(seg0 + (tip[:2] - (x1, y1)) @ u, abs=1e-9)


def test_the_pegs_depth_is_below_the_holes_top_within_its_radius():
    """Down the hole's axis, 1.5 mm off it, over its chamfer 1 mm below the top (8 mm off the axis:
    past the hole's 7 mm radius, so not in it), and on the block beside it."""
    m, d = free_scene()
    h = CONTEST.hole
    cases = ((0.0, 0.03, 0.03), (0.0015, 0.045, 0.045), (0.008, 0.001, 0.0), (0.012, -0.0005, 0.0))
    for off, below, depth in cases:
        z = h.top_z_m - below
        place_tip(m, d, (h.center_xy_m[0] + off, h.center_xy_m[1], z))
        row, _ = world_row(m, d)
        assert row["peg_depth"] == pytest.approx(depth, abs=1e-9)
        assert row["peg_tip"] == pytest.approx([h.center_xy_m[0] + off, h.center_xy_m[1], z], abs=1e-9)


def break_egg(velocity, push, ramp_s=0.0, steps=3000):
    """The peg 1 mm over (or beside) the egg, moving at ``velocity`` (m/s) and pushed by ``push``
    (N; reached over ``ramp_s``) until the egg breaks; returns the C row at the break and the tip's
    speed down when the contact it broke in began (by MuJoCo's positions, not the row)."""
    m, d = free_scene()
    e = CONTEST.egg
    start = np.array([*e.center_xy_m, e.top_z_m + 0.001])
    if velocity[2] == 0:  # from the side, at the egg's widest
        start = np.array(
            [
                e.center_xy_m[0] - e.diameter_m / 2 - CONTEST.peg.diameter_m / 2 - 0.001,
                e.center_xy_m[1],
                e.top_z_m - e.height_m / 2,
            ]
        )
    place_tip(m, d, start)
    tip = m.site(PEG_TIP_SITE).id
    jac = np.zeros((3, m.nv))
    mujoco.mj_jacSite(m, d, jac, None, tip)
    d.qvel[:] = np.linalg.lstsq(jac, np.asarray(velocity, float), rcond=None)[0]
    state, touch_speed, last_z = None, None, None
    for k in range(steps):
        share = min(1.0, k * m.opt.timestep / ramp_s) if ramp_s else 1.0
        d.qfrc_applied[:] = 0.0
        mujoco.mj_applyFT(
            m,
            d,
            share * np.asarray(push, float),
            np.zeros(3),
            d.site_xpos[tip].copy(),
            m.body(PEG_BODY).id,
            d.qfrc_applied,
        )
        mujoco.mj_step(m, d)
        z = d.site_xpos[tip][2]  # where this step started from: the row's state
        row, state = world_row(m, d, state=state)
        if row["egg_force"] <= 0:  # the peg off the egg (it bounces: the egg is lightly damped)
            touch_speed = None
        elif touch_speed is None:  # this contact began in this step
            touch_speed = (last_z - z) / m.opt.timestep
        last_z = z
        if row["egg_broken"]:
            return row, touch_speed
    raise AssertionError("the egg did not break")


def test_what_broke_the_egg_a_press_a_fall_a_side_hit():
    """A press (the peg brought down at 1 cm/s, the push growing 40 N in 2 s), a fall (the peg
    coming down at 0.6 m/s, nothing pushing) and a side hit (pushed sideways into the egg's widest):
    the row says which, with the touch's speed MuJoCo's positions give."""
    press, speed = break_egg((0.0, 0.0, -0.01), (0.0, 0.0, -40.0), ramp_s=2.0)
    assert press["egg_broken_by"] == 1 and 0 <= press["egg_touch_speed"] < EGG_FALL_M_S
    assert press["egg_touch_speed"] == pytest.approx(max(speed, 0.0), abs=1e-9)
    fall, speed = break_egg((0.0, 0.0, -0.6), (0.0, 0.0, 0.0), steps=400)
    assert fall["egg_broken_by"] == 3 and fall["egg_touch_speed"] > EGG_FALL_M_S
    assert fall["egg_touch_speed"] == pytest.approx(speed, rel=1e-9)
    f = np.asarray(fall["egg_force_xyz"])
    assert np.hypot(*f[:2]) < -f[2]  # from above
    side, _ = break_egg((0.05, 0.0, 0.0), (40.0, 0.0, 0.0), ramp_s=2.0)
    f = np.asarray(side["egg_force_xyz"])
    assert side["egg_broken_by"] == 2 and np.hypot(*f[:2]) > -f[2]
