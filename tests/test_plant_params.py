"""The plant parameters a run uses (crslab/plant/plant_params.py): params.toml's values, plant files,
values by name, and what the worker makes of them (the model's friction, gear, masses; the C drive)."""

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

from crslab.plant.model import apply_plant, holding_torques_nm, load_model, motor_to_qpos
from crslab.plant.model_files import PARAMS, REST_MOTOR_RAD
from crslab.plant.plant_params import NAMES, PlantParams, PlantParamsError
from crslab.run.api import make_config, simulate

ROOT_FRICTION = PARAMS["friction"]
LAB_TAU1 = Path(__file__).parent / "labs" / "open_loop_tau1.c"


def test_defaults_are_params_toml_values():
    p = PlantParams.defaults()
    assert p.motor_gain == PARAMS["command"]["newton_metre_per_unit"]
    assert p.stall_nm == tuple(PARAMS["drive"]["stall_nm"])
    assert p.backemf_nm_s_per_rad == tuple(PARAMS["drive"]["backemf_nm_s_per_rad"])
    assert p.drive_lag_s == PARAMS["drive"]["lag_s"]
    for m in (1, 2, 3):
        row = ROOT_FRICTION[f"motor{m}"]
        assert p.value(f"coulomb_pos{m}") == row["Cpos_nm"]
        assert p.value(f"coulomb_neg{m}") == row["Cneg_nm"]
        assert p.value(f"viscous_pos{m}") == row["Vpos_nm_s_per_rad"]
        assert p.value(f"viscous_neg{m}") == row["Vneg_nm_s_per_rad"]
        assert p.value(f"static_pos{m}") == row["Spos_nm"]
        assert p.value(f"static_neg{m}") == row["Sneg_nm"]
        assert p.value(f"rotor_inertia{m}") == PARAMS["rotor"][f"motor{m}"]
    assert p.friction_transition_rad_s == ROOT_FRICTION["transition_rad_s"]
    assert p.friction_scale == (1.0, 1.0, 1.0) and p.mass_scale == 1.0 and p.payload_kg == 0.0


def test_the_symmetric_band_and_its_constant_torque_give_spos_and_sneg():
    """MuJoCo's friction is -half sliding positive and +half sliding negative; with the constant
    torque b added the joint feels -Spos and -Sneg (and sticks in between)."""
    p = PlantParams.defaults().with_values({"static_pos1": 1.0, "static_neg1": -3.0})
    half, bias = p.band_half_nm()[0], p.friction_bias_nm()[0]
    assert (half, bias) == (2.0, 1.0)
    assert -half + bias == -1.0 and half + bias == 3.0
    for m in range(3):
        half, bias = p.band_half_nm()[m], p.friction_bias_nm()[m]
        assert -half + bias == pytest.approx(-p.static_pos_nm[m])
        assert half + bias == pytest.approx(-p.static_neg_nm[m])


def test_names_reach_every_field_and_sweep_names_exist():
    p = PlantParams.defaults()
    for name in ("friction", "friction1", "friction2", "friction3", "payload_kg", "mass", "motor_gain",
                 "encoder_noise_counts"):
        assert name in NAMES
    q = p.with_values({"friction": 2.0, "friction3": 0.5, "mass": 1.3, "motor_gain": 5.0, "payload_kg": 0.4,
                       "encoder_noise_counts": 2.0, "backemf2": 0.5, "drive_lag_s": 0.003})
    assert q.friction_scale == (2.0, 2.0, 1.0)  # friction3 multiplies the overall scale
    assert (q.mass_scale, q.motor_gain, q.payload_kg, q.encoder_noise_counts) == (1.3, 5.0, 0.4, 2.0)
    assert q.backemf_nm_s_per_rad[1] == 0.5 and q.drive_lag_s == 0.003
    assert q.band_half_nm()[0] == pytest.approx(2.0 * p.band_half_nm()[0])
    assert q.friction_nm(1, 0.7) == pytest.approx(2.0 * p.friction_nm(1, 0.7))
    assert q.friction_nm(3, -0.7) == pytest.approx(p.friction_nm(3, -0.7))  # 2.0 * 0.5


@pytest.mark.parametrize("values, words", [
    ({"frictoin": 1.0}, "no plant value called 'frictoin'"),
    ({"payload_kg": -1.0}, "payload_kg = -1.0 is outside 0 .. 10"),
    ({"payload_kg": 10.5}, "payload_kg = 10.5 is outside 0 .. 10"),
    ({"coulomb_neg2": 1.0}, "coulomb_neg2 = 1.0 is outside -1000 .. 0"),
    ({"mass": 0.0}, "mass = 0.0 is outside 0.01 .. 100"),
    ({"mass": float("nan")}, "mass = nan"),
    ({"viscous_pos1": float("inf")}, "viscous_pos1 = inf"),
    ({"static_neg3": 0.5}, "static_neg3 = 0.5 is outside -1000 .. 0"),
    ({"friction_transition_rad_s": 0.0}, "friction_transition_rad_s = 0.0 is outside 0.005 .. 1"),
    ({"motor_gain": "six"}, "motor_gain must be a number"),
])
def test_bad_values_are_one_line_naming_them(values, words):
    with pytest.raises(PlantParamsError, match=words.replace(".", r"\.").replace("(", r"\(")):
        PlantParams.defaults().with_values(values)


def test_a_plant_file_round_trips_and_overrides_only_what_it_says(tmp_path):
    shipped = PlantParams.defaults()
    path = tmp_path / "arm.toml"
    changed = shipped.with_values({"stall_nm2": 18.6, "coulomb_pos1": 0.9, "friction2": 1.2})
    path.write_text(changed.to_toml("my arm\nfitted today"))
    assert path.read_text().startswith("# my arm\n# fitted today\n")
    assert PlantParams.load(path) == changed
    partial = tmp_path / "partial.toml"
    partial.write_text("[drive]\nlag_s = 0.004\n\n[variations]\npayload_kg = 0.5\n")
    loaded = PlantParams.load(partial)
    assert loaded == shipped.with_values({"drive_lag_s": 0.004, "payload_kg": 0.5})
    ideal = tmp_path / "ideal.toml"
    ideal.write_text("[drive]\nstall_nm = [inf, inf, inf]\n")
    assert math.isinf(PlantParams.load(ideal).stall_nm[0])


@pytest.mark.parametrize("text, words", [
    ("[drive]\nstall = [1, 2, 3]\n", "2: drive.stall: unknown key ([drive] holds stall_nm, "),
    ("[drive]\nstall_nm = [1, 2]\n", "2: drive.stall_nm: must be three numbers (motors 1, 2, 3), got [1, 2]"),
    ("[drive]\nstall_nm = [1, inf, 1001]\n", "2: drive.stall_nm: 1001 is outside 0 .. 1000 (torque the "),
    ("[waist]\nmass = 3\n", "1: waist: unknown table (a plant file holds [command], "),
    ("[friction.motor4]\nCpos_nm = 1\n", "1: friction.motor4: unknown table (motor1, motor2 or motor3)"),
    ("[friction.motor1]\nCpos = 1\n", "2: friction.motor1.Cpos: unknown key (Cpos_nm, "),
    ("[friction.motor1]\n\nSneg_nm = 0.5\n", "3: friction.motor1.Sneg_nm: 0.5 is outside -1000 .. 0 (st"),
    ("[variations]\nfriction1 = -2\n", "2: variations.friction1: -2 is outside 0 .. 100 (scale of all"),
    ("[variations]\npayload_kg = 1e300\n", "2: variations.payload_kg: 1e300 is too large a number"),
    ("[variations]\n# nothing\npayload_kg = 1e-300\n", "3: variations.payload_kg: 1e-300 is too small a"),
    ("[variations]\nmass = " + "9" * 400 + "\n", "2: variations.mass: a whole number of 400 digits is too"),
    ("[command]\nnewton_metre_per_unit = true\n", "2: command.newton_metre_per_unit: must be a number, got"),
    ("drive = ", " not valid TOML"),
])
def test_bad_plant_files_are_one_line_naming_file_line_and_key(tmp_path, text, words):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(PlantParamsError) as exc:
        PlantParams.load(path)
    message = str(exc.value)
    assert message.startswith(f"{path}:{words}") and "\n" not in message, message
    with pytest.raises(PlantParamsError, match="no such plant file"):
        PlantParams.load(tmp_path / "missing.toml")


def test_apply_plant_sets_friction_gear_masses_and_payload():
    loaded = load_model()
    model = load_model()
    p = PlantParams.defaults().with_values({"friction": 0.5, "motor_gain": 4.0, "mass": 1.5,
                                            "payload_kg": 0.3})
    apply_plant(model, p, loaded=loaded)
    half = PlantParams.defaults().band_half_nm()
    np.testing.assert_allclose(model.dof_frictionloss, [0.5 * half[0], 0.5 * half[1], 0.0])
    np.testing.assert_allclose(model.tendon_frictionloss, [0.5 * half[2]])
    np.testing.assert_allclose(model.actuator_gear[:, 0], 4.0)
    for name in ("upper_arm", "forearm"):
        assert model.body(name).mass[0] == pytest.approx(1.5 * loaded.body(name).mass[0])
        np.testing.assert_allclose(model.body(name).inertia, 1.5 * loaded.body(name).inertia)
    assert model.body("payload").mass[0] == pytest.approx(0.3)
    apply_plant(model, p, loaded=loaded)  # applying twice does not compound
    assert model.body("forearm").mass[0] == pytest.approx(1.5 * loaded.body("forearm").mass[0])
    # the world carries every body: its subtree mass follows
    assert model.body_subtreemass[0] == pytest.approx(model.body_mass.sum())


def test_the_generated_model_is_the_default_plant_applied():
    model, reference = load_model(), load_model()
    apply_plant(model, PlantParams.defaults(), loaded=reference)
    for field in ("dof_frictionloss", "dof_damping", "tendon_frictionloss", "tendon_damping", "actuator_gear",
                  "actuator_biasprm", "dof_armature", "tendon_armature",
                  "body_mass", "body_inertia", "body_subtreemass"):
        np.testing.assert_allclose(getattr(model, field), getattr(reference, field), err_msg=field)


def test_shipped_friction_holds_the_arm_at_its_resting_pose():
    """The real arm rests where it is put with zero torque (docs/framework.md section 11): gravity
    at the resting pose must lie inside every motor's static band [Sneg, Spos]."""
    p = PlantParams.defaults()
    hold = holding_torques_nm(REST_MOTOR_RAD)
    for m in range(3):
        assert -p.static_neg_nm[m] >= hold[m] and p.static_pos_nm[m] >= -hold[m], m


def test_holding_torques_are_gravity_in_motor_coordinates():
    # hand-derived from the course's model: motor 2 carries p4 g sin th2M, motor 3 p5 g cos th3M (x 6 N.m)
    rest = np.array([0.0, -0.3, 0.5])
    hold = holding_torques_nm(rest)
    # the model matches the course's p4 = 0.0753, p5 = 0.0298 units to 1 % (test_crs_model.py)
    assert hold[1] == pytest.approx(-6 * 0.0753 * 9.81 * np.sin(rest[1]), rel=0.02)
    assert hold[2] == pytest.approx(-6 * 0.0298 * 9.81 * np.cos(rest[2]), rel=0.02)
    model = load_model()
    data = mujoco.MjData(model)
    data.qpos[:3] = motor_to_qpos(rest)
    mujoco.mj_forward(model, data)
    assert hold[0] == pytest.approx(0.0, abs=1e-12)


def test_a_run_uses_the_plant_file(tmp_path):
    """A lab holding tau1 = 1 unit (6 N.m): with a drive that gives at most 3 N.m at standstill the
    waist turns slower, and with the shipped one (16.5 N.m) exactly as fast as with an ideal drive
    until the back-EMF limit is near (6 N.m at w < (16.5 - 6) / 4.37 = 2.4 rad/s)."""
    weak, ideal = tmp_path / "weak.toml", tmp_path / "ideal.toml"
    weak.write_text("[drive]\nstall_nm = [3.0, 3.0, 3.0]\n")
    ideal.write_text("[drive]\nstall_nm = [inf, inf, inf]\nbackemf_nm_s_per_rad = [0, 0, 0]\n")
    assert make_config(LAB_TAU1, plant=weak).plant.stall_nm == (3.0, 3.0, 3.0)

    def turned(plant):
        run = simulate(LAB_TAU1, "hands_off", duration_s=0.05, startup_delay=False, log=True, plant=plant)
        return float(run.log["enc_rad"][-1, 0])

    shipped, slow, free = turned(None), turned(weak), turned(ideal)
    assert 0 < slow < 0.6 * shipped
    assert shipped == pytest.approx(free, rel=1e-6)


def test_a_plant_files_variations_reach_the_run(tmp_path):
    """Encoder noise of 3 counts (every joint, seeded) makes the resting arm's readings jitter by
    about that much; a payload makes the resting forearm sag (the run holds no torque)."""
    noisy, heavy = tmp_path / "noisy.toml", tmp_path / "heavy.toml"
    noisy.write_text("[variations]\nencoder_noise_counts = 3.0\n")
    heavy.write_text("[variations]\npayload_kg = 1.5\n")
    quiet = simulate(LAB_TAU1, "hands_off", duration_s=0.5, log=True, plant=None)
    jitter = simulate(LAB_TAU1, "hands_off", duration_s=0.5, log=True, plant=noisy)
    counts = np.diff(jitter.log["enc_rad"][:, 1:], axis=0) / (np.pi / 144000)
    assert np.all(np.diff(quiet.log["enc_rad"][:, 1:], axis=0) == 0)
    assert 3.0 < counts.std() < 5.5  # the difference of two readings: sqrt(2) x 3 counts
    sag = simulate(LAB_TAU1, "hands_off", duration_s=1.0, log=True, plant=heavy)
    assert sag.log["enc_rad"][-1, 2] - sag.log["enc_rad"][0, 2] > 0.05  # the forearm falls


def test_a_plant_file_of_before_reads_as_the_arm_it_described(tmp_path):
    """Before the course's lines, a plant file had one V_nm_s_per_rad and no static band: both
    slopes take that value and the band is the Coulomb values (a joint stuck within [Cneg, Cpos],
    as plain dry friction has it); [rotor] and [friction] transition_rad_s set the rotors and the
    transition; a key [friction] does not know is one line naming it."""
    old = tmp_path / "old.toml"
    old.write_text("[friction.motor2]\nCpos_nm = 1.28\nCneg_nm = -2.14\nV_nm_s_per_rad = 0.24\n"
                   "[rotor]\nmotor1 = 0.0\nmotor2 = 0.075\nmotor3 = 0.0375\n"
                   "[friction]\ntransition_rad_s = 0.05\n")
    p = PlantParams.load(old)
    assert (p.viscous_pos_nm_s_per_rad[1], p.viscous_neg_nm_s_per_rad[1]) == (0.24, 0.24)
    assert p.static_band_nm(2) == (-2.14, 1.28)
    assert p.rotor_inertia_kg_m2 == (0.0, 0.075, 0.0375) and p.friction_transition_rad_s == 0.05
    assert p.static_pos_nm[0] == PlantParams.defaults().static_pos_nm[0]  # motor 1: not in the file
    # with no gap between the band and the line nothing changes at the band's edge: the law is the line
    assert p.friction_nm(2, 1e-6) == pytest.approx(1.28, abs=1e-6)
    assert p.friction_nm(2, -0.5) == pytest.approx(-2.14 - 0.24 * 0.5)
    bad = tmp_path / "bad.toml"
    bad.write_text("[friction]\nwidth = 1\n")
    with pytest.raises(PlantParamsError) as caught:
        PlantParams.load(bad)
    assert str(caught.value) == (f"{bad}:2: friction.width: unknown key ([friction] holds transition_rad_s, "
                                 "and the tables [friction.motor1..3])")


def test_the_law_rises_from_the_band_edge_to_the_line_over_the_transition_speed():
    """Hand-computed: Spos 1.0, Cpos 1.5, Vpos 0.2, w_t 0.02 rad/s. At w = w_t the gap is
    1 - 1/e of the way; at 10 w_t all but e^-10 of it; moving negative the other side's numbers."""
    p = PlantParams.defaults().with_values({
        "static_pos1": 1.0, "coulomb_pos1": 1.5, "viscous_pos1": 0.2, "static_neg1": -2.0,
        "coulomb_neg1": -1.8, "viscous_neg1": 0.4, "friction_transition_rad_s": 0.02})
    assert p.friction_nm(1, 0.02) == pytest.approx(1.0 + 0.5 * (1 - math.exp(-1)) + 0.2 * 0.02)
    assert p.friction_nm(1, 0.2) == pytest.approx(1.5 + 0.2 * 0.2, abs=0.5 * math.exp(-10) + 1e-12)
    # stiction on the negative side: sliding friction falls from -2.0 towards the line -1.8 + 0.4 w
    assert p.friction_nm(1, -0.02) == pytest.approx(-2.0 + 0.2 * (1 - math.exp(-1)) - 0.4 * 0.02)
    assert p.friction_nm(1, 0.0) == 0.0
    assert p.with_values({"friction1": 2.0}).friction_nm(1, 0.3) == pytest.approx(2 * p.friction_nm(1, 0.3))
