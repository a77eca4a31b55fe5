"""The MuJoCo model of the CRS arm (models/crs_arm) against the course's kinematics and dynamics."""

import importlib.util
from pathlib import Path

import mujoco
import numpy as np
import pytest

from crslab import crs
from crslab.plant import model as crs_model
from crslab.plant.model import (
    COURSE_END_MASS_KG,
    REST_MOTOR_RAD,
    SCENE_XML,
    load_model,
    motor_to_qpos,
    qpos_to_motor,
    set_end_mass,
)
from crslab.plant.model_files import PARAMS

ROOT = Path(__file__).resolve().parents[1]
G = 9.81
NM_PER_UNIT = 6.0  # docs/framework.md section 11
# The course's 2-link model in motor angles and command units (docs/framework.md section 11).
P_BARE = (0.0300, 0.0128, 0.0076, 0.0753, 0.0298)
P_END_MASS = (0.0466, 0.0388, 0.0284, 0.1405, 0.1298)
COURSE_ROTOR = (0.075, 0.0375)  # kg.m^2, motors 2 and 3: the rotor inertia the course's p1 and p2 hold
ROTOR = tuple(PARAMS["rotor"][f"motor{m}"] for m in (1, 2, 3))  # what crslab's arm has (fitted)


def course_d(p, motor):
    """The course's D in N.m per rad/s^2 for ``p``, with the course's rotor inertias replaced by the
    arm's (params.toml [rotor]): the links are the course's, the rotors crslab's fitted ones."""
    p1, p2, p3 = (NM_PER_UNIT * v for v in p[:3])
    p1 += ROTOR[1] - COURSE_ROTOR[0]
    p2 += ROTOR[2] - COURSE_ROTOR[1]
    s = np.sin(motor[2] - motor[1])
    return np.array([[p1, -p3 * s], [-p3 * s, p2]])

MOTOR_ZERO = (0.0, 0.0, 0.0)
DH_ZERO = (0.0, np.pi / 2, 0.0)
STRAIGHT_UP = (0.0, 0.0, -np.pi / 2)


@pytest.fixture(scope="module")
def model():
    return load_model()


def fresh(model, motor_rad, ctrl=(0.0, 0.0, 0.0)):
    """A new MjData at rest in the given motor pose, with constant controls."""
    data = mujoco.MjData(model)
    data.qpos[:] = motor_to_qpos(motor_rad)
    data.ctrl[:] = ctrl
    mujoco.mj_forward(model, data)
    return data


def run(model, data, seconds):
    """Step for a whole number of 1 ms steps; return the motor angles after each step."""
    steps = int(round(seconds / model.opt.timestep))
    out = np.empty((steps, 3))
    for k in range(steps):
        mujoco.mj_step(model, data)
        out[k] = qpos_to_motor(data.qpos)
    return out


def warnings(data):
    return {mujoco.mjtWarning(i).name: w.number for i, w in enumerate(data.warning) if w.number}


def motor_space_gravity(model, data):
    """Gravity's term G of D qdd + G = tau, in motor coordinates for motors 2 and 3 (N.m).

    At zero velocity qfrc_bias is G in DH coordinates. With q2 = th2M - pi/2 and
    q3 = th3M - th2M + pi/2, virtual work gives G2M = G2 - G3 and G3M = G3.
    """
    assert not data.qvel.any()
    g2, g3 = data.qfrc_bias[1], data.qfrc_bias[2]
    return np.array([g2 - g3, g3])


def motor_space_inertia(model, data):
    """The 2x2 mass matrix of motors 2 and 3 in motor coordinates (kg.m^2): A^T M A."""
    full = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, full)
    a = np.array([[1.0, 0.0], [-1.0, 1.0]])  # d(q2, q3) / d(th2M, th3M)
    return a.T @ full[1:, 1:] @ a


# --- the files and names others code against -------------------------------------------------

def test_scene_loads_with_the_course_timestep_and_steps_without_warnings(model):
    assert SCENE_XML.is_file() and SCENE_XML.parent == crs_model.MODEL_DIR
    assert model.opt.timestep == 0.001
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    np.testing.assert_array_equal(model.opt.gravity, [0, 0, -9.81])
    data = fresh(model, REST_MOTOR_RAD)
    rng = np.random.default_rng(3)
    for _ in range(20):  # random clamped commands, 100 ms each: big swings, limits hit
        data.ctrl[:] = rng.uniform(-5, 5, 3)
        run(model, data, 0.1)
    assert warnings(data) == {}
    assert np.isfinite(data.qpos).all() and np.isfinite(data.qvel).all()


def test_joints_actuators_and_tendon_are_named_and_ordered_as_documented(model):
    assert [model.joint(i).name for i in range(model.njnt)] == ["j1", "j2", "j3"]
    assert [int(model.joint(n).qposadr[0]) for n in ("j1", "j2", "j3")] == [0, 1, 2]
    assert [int(model.joint(n).dofadr[0]) for n in ("j1", "j2", "j3")] == [0, 1, 2]
    assert all(model.jnt_type == mujoco.mjtJoint.mjJNT_HINGE) and all(model.jnt_limited)
    assert [model.actuator(i).name for i in range(model.nu)] == ["motor1", "motor2", "motor3"]
    assert model.actuator("motor3").trntype[0] == mujoco.mjtTrn.mjTRN_TENDON
    assert model.tendon(int(model.actuator("motor3").trnid[0])).name == "forearm"
    np.testing.assert_array_equal(model.actuator_gear[:, 0], [NM_PER_UNIT] * 3)
    assert not model.actuator_ctrllimited.any()  # the framework clamps, not the plant
    assert model.site("ee").id >= 0 and model.body("payload").id >= 0
    # no contacts anywhere: every geom is a visual
    assert not model.geom_contype.any() and not model.geom_conaffinity.any()


def test_actuators_give_the_course_torque_relations(model):
    # docs/framework.md section 10: tau2DH = tau2M + tau3M, tau3DH = tau3M, with 6 N.m per command
    # unit; each motor also carries the constant torque of its static band's asymmetry,
    # -(Spos + Sneg) / 2 (params.toml)
    rows = [PARAMS["friction"][f"motor{m}"] for m in (1, 2, 3)]
    bias = [-(row["Spos_nm"] + row["Sneg_nm"]) / 2 for row in rows]
    data = fresh(model, REST_MOTOR_RAD)
    np.testing.assert_allclose(data.qfrc_actuator, [bias[0], bias[1] + bias[2], bias[2]], atol=1e-12)
    data = fresh(model, REST_MOTOR_RAD, ctrl=(0.5, -1.25, 2.0))
    torque = NM_PER_UNIT * np.array([0.5, -1.25, 2.0]) + bias
    np.testing.assert_allclose(data.qfrc_actuator, [torque[0], torque[1] + torque[2], torque[2]], atol=1e-12)
    # the tendon's length is motor angle 3, whatever the pose
    rng = np.random.default_rng(5)
    for motor in rng.uniform(-1.5, 1.5, (20, 3)):
        data = fresh(model, motor)
        assert data.ten_length[0] == pytest.approx(motor[2], abs=1e-12)


def test_rest_keyframe_and_lab_poses_lie_inside_the_joint_ranges(model):
    rest_key = model.key("rest")
    np.testing.assert_allclose(rest_key.qpos, motor_to_qpos(REST_MOTOR_RAD), atol=1e-10)
    margin = np.radians(5)
    lo, hi = model.jnt_range[:, 0], model.jnt_range[:, 1]
    for name, motor in [("rest", REST_MOTOR_RAD), ("motor zero", MOTOR_ZERO), ("DH zero", DH_ZERO),
                        ("straight up", STRAIGHT_UP), ("template rest", (0.0, -0.37, 0.27))]:
        q = motor_to_qpos(motor)
        assert (q > lo + margin).all() and (q < hi - margin).all(), name
    for key in ("motor_zero", "dh_zero", "straight_up"):
        expected = {"motor_zero": MOTOR_ZERO, "dh_zero": DH_ZERO, "straight_up": STRAIGHT_UP}[key]
        np.testing.assert_allclose(qpos_to_motor(model.key(key).qpos), expected, atol=1e-10)


# --- kinematics -------------------------------------------------------------------------------

def test_model_fk_equals_the_c_core_fk_at_random_poses(model):
    data = mujoco.MjData(model)
    site = model.site("ee").id
    rng = np.random.default_rng(2024)
    motor = rng.uniform(-np.pi, np.pi, (200, 3))
    expected_m = crs.fk(motor) * crs.M_PER_IN
    poses = crs.fk_pose_dh(crs.motor_to_dh(motor))
    for i in range(len(motor)):
        data.qpos[:] = motor_to_qpos(motor[i])
        mujoco.mj_kinematics(model, data)
        np.testing.assert_allclose(data.site_xpos[site], expected_m[i], rtol=0, atol=1e-9)
        # the site's frame is DH frame 3, so the body frames really follow the DH table
        np.testing.assert_allclose(data.site_xmat[site].reshape(3, 3), poses[i, :3, :3], atol=1e-9)


def test_course_check_poses_in_metres(model):
    site = model.site("ee").id
    for motor, xyz_in in [(MOTOR_ZERO, (10, 0, 20)), (DH_ZERO, (20, 0, 10)), (STRAIGHT_UP, (0, 0, 30))]:
        data = fresh(model, motor)
        np.testing.assert_allclose(data.site_xpos[site], np.array(xyz_in) * 0.0254, atol=1e-9)


# --- dynamics ---------------------------------------------------------------------------------

def test_gravity_torques_match_the_course_p_values(model):
    # Course: G = [-p4 g sin th2M, -p5 g cos th3M] in command units (docs/framework.md section 11).
    rng = np.random.default_rng(11)
    for motor in rng.uniform(-1.5, 1.5, (50, 3)):
        data = fresh(model, motor)
        course = NM_PER_UNIT * G * np.array([-P_BARE[3] * np.sin(motor[1]), -P_BARE[4] * np.cos(motor[2])])
        amplitude = NM_PER_UNIT * G * np.array([P_BARE[3], P_BARE[4]])
        np.testing.assert_array_less(np.abs(motor_space_gravity(model, data) - course), 0.01 * amplitude)


def test_inertia_matches_the_course_d_matrix_with_the_fitted_rotors(model):
    # Course: D = [[p1, -p3 sin(th3M - th2M)], [., p2]] in command units, its rotor inertias (0.075,
    # 0.0375) included; crslab's arm has the links of the course and rotors fitted to the real arm.
    rng = np.random.default_rng(12)
    for motor in rng.uniform(-1.5, 1.5, (50, 3)):
        data = fresh(model, motor)
        np.testing.assert_allclose(motor_space_inertia(model, data), course_d(P_BARE, motor),
                                   rtol=0, atol=0.02 * NM_PER_UNIT * P_BARE[1])


def test_course_end_mass_reproduces_the_course_p_values_with_end_mass():
    model = load_model()
    set_end_mass(model, COURSE_END_MASS_KG)
    d_course = course_d(P_END_MASS, (0.0, 0.0, 0.0))
    for motor in [REST_MOTOR_RAD, DH_ZERO, (0.3, 0.8, -0.6)]:
        data = fresh(model, motor)
        inertia = motor_space_inertia(model, data)
        # p1: the mass at the elbow's distance, as the course has it
        assert inertia[0, 0] == pytest.approx(d_course[0, 0], rel=0.02)
        # gravity, p4 and p5, exactly (the placement is fitted to them, README)
        np.testing.assert_allclose(motor_space_gravity(model, data),
                                   [-NM_PER_UNIT * P_END_MASS[3] * G * np.sin(motor[1]),
                                    -NM_PER_UNIT * P_END_MASS[4] * G * np.cos(motor[2])], rtol=0, atol=0.003)
    # p2 and p3 with the mass are not what a lump 0.39 m from the elbow gives (the course's five
    # values fit no single rigid body, README): the model's are pinned so a change is deliberate
    data = fresh(model, MOTOR_ZERO)
    inertia = motor_space_inertia(model, data)
    rotor_extra = ROTOR[2] - COURSE_ROTOR[1]
    assert (inertia[1, 1] - rotor_extra) / NM_PER_UNIT == pytest.approx(0.0518, abs=0.0005)
    data = fresh(model, (0.0, 0.0, np.pi / 2))  # sin(th3M - th2M) = 1
    assert -motor_space_inertia(model, data)[0, 1] / NM_PER_UNIT == pytest.approx(0.0330, abs=0.0005)
    set_end_mass(model, 0.0)
    data = fresh(model, DH_ZERO)
    assert motor_space_gravity(model, data)[0] == pytest.approx(-NM_PER_UNIT * P_BARE[3] * G, rel=0.01)
    assert model.body_subtreemass[0] == pytest.approx(load_model().body_subtreemass[0])


def test_with_the_end_mass_gravity_is_the_course_p_vectors_over_the_workspace():
    """Lab 3's end mass: over a grid of poses inside the safety envelope, gravity on motors 2 and 3
    agrees with the course's G = [-p4 g sin th2M, -p5 g cos th3M] for its p vector with the end mass
    within 5 % (of the larger of the two torques at that pose), and without it for the bare arm."""
    from crslab.plant.model import holding_torques_nm
    from crslab.plant.plant_params import PlantParams

    grid = [(t1, t2, t3) for t1 in (-1.5, 0.0, 1.5) for t2 in np.linspace(-0.7, 1.6, 12)
            for t3 in np.linspace(-1.9, 1.2, 12)]
    inside = [m for m in grid if not crs.outside_envelope(np.array(m))]
    assert len(inside) > 150
    for kg, p in ((COURSE_END_MASS_KG, P_END_MASS), (0.0, P_BARE)):
        plant = PlantParams.defaults().with_values({"payload_kg": kg})
        worst = 0.0
        for motor in inside:
            hold = holding_torques_nm(motor, plant) / NM_PER_UNIT  # the command that holds the arm, units
            course = np.array([-p[3] * G * np.sin(motor[1]), -p[4] * G * np.cos(motor[2])])
            worst = max(worst, float(np.max(np.abs(hold[1:] - course)) / np.max(np.abs(course))))
        assert worst < 0.05, (kg, worst)


def test_static_band_and_rotor_inertia_come_from_params_toml(model):
    # MuJoCo's dry friction is symmetric: half the width of the static band [Sneg, Spos]; its offset
    # is the actuators' bias (above); the friction while sliding is the C board's, so no damping.
    # Motors 1, 2 on j1, j2; motor 3 on the forearm tendon.
    rows = [PARAMS["friction"][f"motor{m}"] for m in (1, 2, 3)]
    half = [(r["Spos_nm"] - r["Sneg_nm"]) / 2 for r in rows]
    np.testing.assert_allclose(model.dof_frictionloss, [half[0], half[1], 0])
    np.testing.assert_allclose(model.tendon_frictionloss, [half[2]])
    assert not model.dof_damping.any() and not model.tendon_damping.any()
    np.testing.assert_allclose(model.dof_armature, [ROTOR[0], ROTOR[1], 0])
    np.testing.assert_allclose(model.tendon_armature, [ROTOR[2]])


def test_with_zero_torque_the_arm_stays_at_its_resting_pose(model):
    data = fresh(model, REST_MOTOR_RAD)
    path = run(model, data, 10.0)
    assert np.abs(path - REST_MOTOR_RAD).max() < 0.01
    assert warnings(data) == {}


def test_released_level_arm_falls_shoulder_down_but_the_upright_arm_stays(model):
    # Derivation. In motor angles the course's model is D qdd + G = u, G2 = -p4 g sin th2M, so
    # gravity pushes motor 2 with +p4 g sin th2M: at DH zero (th2M = pi/2, arm level) that is
    # 0.0753 * 9.81 = 0.74 units = 4.43 N.m, more than motor 2's dry friction against positive
    # motion (Cpos2, params.toml): th2M grows, the upper arm swings down and
    # z = 10 (1 + cos th2M - sin th3M) falls. At motor zero (upper arm up, forearm level) gravity
    # leaves motor 2 alone and pushes motor 3 with p5 g cos 0 = 0.29 units = 1.75 N.m, less than
    # Cpos3: nothing moves.
    data = fresh(model, DH_ZERO)
    z0 = data.site_xpos[model.site("ee").id, 2]
    path = run(model, data, 0.3)
    assert path[-1, 1] > DH_ZERO[1] + 0.1
    limit = np.pi / 2 + model.jnt_range[1, 1]  # j2's range, in motor angle 2
    falling = path[:, 1] < limit - 0.01
    assert np.all(np.diff(path[:, 1])[falling[1:]] >= -1e-9)  # it only falls, until the range stops it
    assert data.site_xpos[model.site("ee").id, 2] < z0 - 0.02
    assert PARAMS["friction"]["motor3"]["Spos_nm"] > 6 * P_BARE[4] * G
    data = fresh(model, MOTOR_ZERO)
    assert np.abs(run(model, data, 1.0) - MOTOR_ZERO).max() < 1e-9


@pytest.mark.parametrize("motor", [0, 1, 2])
@pytest.mark.parametrize("sign", [+1, -1])
def test_ctrl_turns_its_motor_angle_the_same_way(model, motor, sign):
    ctrl = np.zeros(3)
    ctrl[motor] = 1.5 * sign
    data = fresh(model, REST_MOTOR_RAD, ctrl)
    moved = run(model, data, 0.2)[-1] - REST_MOTOR_RAD
    assert sign * moved[motor] > 0.05


def test_motor3_drives_the_forearm_absolute_angle_and_leaves_the_shoulder(model):
    # Motor 3's torque enters motor 2's equation only through the inertial coupling
    # -p3 sin(th3M - th2M); a joint-3 (relative) drive would push the shoulder back with the full
    # reaction torque instead. Without gravity and friction, the first instant's accelerations
    # (motor angles) are the course's D^-1 u.
    bare = load_model()
    bare.opt.gravity[:] = 0
    bare.dof_frictionloss[:] = 0
    bare.tendon_frictionloss[:] = 0
    bare.actuator_biasprm[:] = 0

    def accel(ctrl):
        data = fresh(bare, REST_MOTOR_RAD, ctrl)
        qacc = data.qacc.copy()
        return np.array([qacc[0], qacc[1], qacc[1] + qacc[2]])  # motor angles 1, 2, 3

    by_motor2, by_motor3 = accel((0.0, 1.0, 0.0)), accel((0.0, 0.0, 1.0))
    d = course_d(P_BARE, REST_MOTOR_RAD) / NM_PER_UNIT  # command units
    np.testing.assert_allclose(by_motor3[1:], np.linalg.solve(d, [0.0, 1.0]), rtol=0.02)
    np.testing.assert_allclose(by_motor2[1:], np.linalg.solve(d, [1.0, 0.0]), rtol=0.02)
    # a relative (joint-3) drive of the same torque: j3 alone, so motor 2 takes the reaction
    data = fresh(bare, REST_MOTOR_RAD)
    data.qfrc_applied[:] = (0.0, 0.0, NM_PER_UNIT)
    mujoco.mj_forward(bare, data)
    relative = data.qacc[1]
    np.testing.assert_allclose(relative, np.linalg.solve(d, [-1.0, 1.0])[0], rtol=0.02)
    assert by_motor3[1] > 0 > relative  # the shoulder is nudged forward, never pulled back


# --- the generated files ------------------------------------------------------------------------

def test_generator_reproduces_the_committed_files():
    path = ROOT / "tools" / "gen_crs_model.py"
    spec = importlib.util.spec_from_file_location("gen_crs_model", path)
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    files = gen.build()
    assert {p.name for p in files} == {"crs_arm.xml", "scene.xml"}
    for file, text in files.items():
        assert file.read_text() == text, f"{file.name} is stale: run python tools/gen_crs_model.py"


# --- the MuJoCo stages the arm skips (params.toml [solver] disable) ---------------------------------

CONTACT, ISLAND = mujoco.mjtDisableBit.mjDSBL_CONTACT, mujoco.mjtDisableBit.mjDSBL_ISLAND


def collidable_pairs(m):
    """The geom pairs MuJoCo's collision stage could make a contact of: an explicit <pair>, or two
    geoms of different bodies whose contype of one meets the conaffinity of the other."""
    pairs = [(int(m.pair_geom1[i]), int(m.pair_geom2[i])) for i in range(m.npair)]
    for i in range(m.ngeom):
        for j in range(i + 1, m.ngeom):
            if m.geom_bodyid[i] != m.geom_bodyid[j] and (
                m.geom_contype[i] & m.geom_conaffinity[j] or m.geom_contype[j] & m.geom_conaffinity[i]
            ):
                pairs.append((i, j))
    return pairs


def every_scene():
    from crslab.world import WORLD_NAMES, load_world
    from crslab.world.scene import load_scene

    return {name: load_scene(load_world(name)) for name in WORLD_NAMES}


def test_params_toml_names_the_stages_the_scene_skips():
    assert PARAMS["solver"]["disable"] == ["contact", "island"]
    option = __import__("xml.etree.ElementTree").etree.ElementTree.parse(SCENE_XML).find("option")
    assert option.find("flag").attrib == {"contact": "disable", "island": "disable"}


def test_contacts_are_skipped_exactly_when_a_scene_has_no_collidable_pair():
    scenes = every_scene()
    assert set(scenes) >= {"none", "contest"}
    for name, m in scenes.items():
        skipped = bool(m.opt.disableflags & CONTACT)
        assert skipped == (not collidable_pairs(m)), name
    assert scenes["none"].opt.disableflags & CONTACT  # the arm alone: nothing to touch
    assert not scenes["contest"].opt.disableflags & CONTACT


def test_islands_are_skipped_in_every_scene_each_one_kinematic_tree():
    # the reason skipping them changes nothing: one tree's constraints make at most one island
    for name, m in every_scene().items():
        assert m.opt.disableflags & ISLAND, name
        assert m.ntree == 1, name


def steps_with_and_without_skipping(m, drive, steps):
    """Per run (``m`` as compiled, then a copy skipping no stage): qpos, qvel and qacc after each
    step, the contacts seen and the steps a joint limit was active, ``drive(k, data)`` setting each
    step's inputs; both from the model's first keyframe."""
    runs = []
    for flags in (m.opt.disableflags, m.opt.disableflags & ~(CONTACT | ISLAND)):
        mm = __import__("copy").copy(m)
        mm.opt.disableflags = flags
        d = mujoco.MjData(mm)
        if mm.nkey:
            mujoco.mj_resetDataKeyframe(mm, d, 0)
        states, contacts, at_limit = [], 0, 0
        for k in range(steps):
            drive(k, d)
            mujoco.mj_step(mm, d)
            states.append(np.concatenate([d.qpos, d.qvel, d.qacc]))
            contacts += d.ncon
            at_limit += d.nl > 0
        runs.append((np.array(states), contacts, at_limit))
    return runs


def test_the_free_air_arm_steps_bit_for_bit_as_without_skipping_through_limits_and_stiction():
    m = load_model()
    rng = np.random.default_rng(3)
    # held still (dry friction holds), then torques large enough to slide and to reach joint limits
    ctrl = np.concatenate([np.zeros((500, 3)), rng.uniform(-6, 6, (2500, 3)), np.zeros((500, 3))])
    kicks = rng.normal(0.0, 20.0, (3500, 3))

    def drive(k, d):
        d.ctrl[:] = ctrl[k]
        d.qfrc_applied[:3] = kicks[k] if 1000 <= k < 1200 else 0.0

    (skipping, _, at_limit), (full, contacts, _) = steps_with_and_without_skipping(m, drive, len(ctrl))
    assert contacts == 0
    assert np.array_equal(skipping, full)  # bit for bit, every step
    assert np.ptp(skipping[:, :3], axis=0).min() > 0.3  # every joint really moved
    assert at_limit > 100  # and ran into its range's end
    assert np.abs(skipping[499, :3] - skipping[0, :3]).max() < 1e-6  # first held by dry friction


def test_a_world_with_contacts_steps_bit_for_bit_as_without_skipping_islands():
    from crslab.world import load_world
    from crslab.world.scene import PEG_BODY, PEG_TIP_SITE, load_scene, set_arm_pose

    world = load_world("contest")
    m = load_scene(world)
    assert not m.opt.disableflags & CONTACT
    h = world.hole
    above_block = np.array((h.center_xy_m[0] + 0.025, h.center_xy_m[1], h.top_z_m + 0.003))
    start = crs.ik_dh(above_block / crs.M_PER_IN)
    peg, tip = m.body(PEG_BODY).id, m.site(PEG_TIP_SITE).id

    def drive(k, d):
        if k == 0:
            set_arm_pose(m, d, start)
            mujoco.mj_forward(m, d)
        d.qfrc_applied[:] = 0.0
        force = (0.0, 0.0, -30.0) if k < 1500 else (8.0, 3.0, -20.0)  # press on the block, then slide
        mujoco.mj_applyFT(m, d, np.array(force), np.zeros(3), d.site_xpos[tip].copy(), peg, d.qfrc_applied)

    (skipping, touched, _), (full, touched_full, _) = steps_with_and_without_skipping(m, drive, 3000)
    assert touched > 1000 and touched == touched_full  # the peg touched the block most steps
    assert np.array_equal(skipping, full)
