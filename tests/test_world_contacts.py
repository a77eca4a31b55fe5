"""The world's contacts do what their materials say (docs/worlds.md), derived, not recorded.

The scene is the contest world's own (crslab.world.scene), stepped by MuJoCo directly with the
arm's joint friction and gravity taken out, so that the only forces are the ones each test
applies and the contact's: a known force on a rigid block and on the egg stops the peg at the
penetration the contact's solref/solimp give; a soft x-y impedance slides the peg into the
chamfered hole from 7 mm off while a stiff one jams on the chamfer (and without the chamfer the
soft one jams too); the scale, the board's C (csrc/plant/world.c), reads the egg's force in grams,
equal to the contact force and to the force the motors' torques give through the course's
Jacobian at rest (J^T F = tau). The board's path: a hand pressing past the breaking force breaks
the egg for the rest of the run, and the scale says so.
"""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest
from crslab._core import ffi, lib

from crslab import crs
from crslab._bindings import compiled_board
from crslab.worker.board import STANDARD_GRAVITY, attach_world
from crslab.world.layout import load_world
from crslab.world.scene import PEG_BODY, PEG_TIP_SITE, load_scene, set_arm_pose

CONTEST = load_world("contest")


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


def world_row(m, d, world=CONTEST):
    """The board's C (crs_world_update) on this state's sensors: the scope row, by name."""
    w = ffi.new("crs_world *")
    lib.crs_world_init(w)
    keep = attach_world(compiled_board(), w, m, d, world)
    lib.crs_world_update(w, 0)
    row = list(w.row)
    del keep
    return {
        "egg_force": row[lib.CRS_WORLD_ROW_EGG_FORCE],
        "scale_g": row[lib.CRS_WORLD_ROW_SCALE_G],
        "egg_broken": row[lib.CRS_WORLD_ROW_EGG_BROKEN],
        "tip": row[0:3],
    }


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
    row = world_row(m, d)
    assert row["egg_force"] == pytest.approx(np.linalg.norm(f[:3]), rel=1e-6)
    assert row["egg_force"] == pytest.approx(np.linalg.norm(from_torques), rel=1e-4)
    assert row["scale_g"] == pytest.approx(-from_torques[2] / STANDARD_GRAVITY * 1000, rel=1e-4)
    assert row["scale_g"] == pytest.approx(normal / STANDARD_GRAVITY * 1000, rel=0.01)  # pressed from above
    assert row["scale_g"] == pytest.approx(7.0 / STANDARD_GRAVITY * 1000, rel=0.01)
    assert np.allclose(row["tip"], d.site_xpos[m.site(PEG_TIP_SITE).id])
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
    down_n = grams[first - 1] * STANDARD_GRAVITY / 1000
    assert 0.5 * force[first - 1] < down_n <= force[first - 1] * (1 + 1e-12)
    assert (force[first + 1 :] == 0).all() and (grams[first + 1 :] == 0).all()  # nothing holds the peg up


def test_the_peg_fits_along_the_whole_groove_its_walls_at_half_the_width_from_the_centre_line():
    """Every groove wall and cap (boxes, in the compiled scene) is farther from the Z's centre line
    than the peg's radius: a peg following the line touches nothing (walls 12 mm thick stuck out
    into the other leg's channel at the sharp corners, 3.4 mm from the line); away from the corners,
    and at the capped ends, the nearest wall is exactly half the groove's width away."""
    world = load_world("contest")
    model = load_scene(world)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    g = world.groove
    corners = np.asarray(g.corners_xy_m)
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, i) or "" for i in range(model.ngeom)]
    walls = [i for i, name in enumerate(names) if name.startswith(("groove_wall", "groove_cap"))]
    assert len(walls) == 8

    def nearest_wall_m(point):
        out = []
        for i in walls:
            rot = data.geom_xmat[i].reshape(3, 3)[:2, :2]
            local = np.abs(rot.T @ (point - data.geom_xpos[i][:2])) - model.geom_size[i][:2]
            out.append(float(np.linalg.norm(np.maximum(local, 0.0))))
        return min(out)

    line = [(i, t, corners[i] + t * (corners[i + 1] - corners[i]))
            for i in range(3) for t in np.linspace(0, 1, 301)]
    distances = [nearest_wall_m(p) for _, _, p in line]
    assert min(distances) > world.peg.diameter_m / 2 + 0.001
    mids = [d for (_, t, _), d in zip(line, distances) if 0.4 <= t <= 0.6]
    assert mids == pytest.approx([g.width_m / 2] * len(mids), abs=1e-9)
    assert nearest_wall_m(corners[0]) == pytest.approx(g.width_m / 2, abs=1e-9)
    assert nearest_wall_m(corners[-1]) == pytest.approx(g.width_m / 2, abs=1e-9)
