"""World files (crslab/world/layout.py): the built-ins load, a bad file is one line naming file,
line and key, a fixture in the arm's way at rest or out of its reach is refused with what and
where, and the command line, the golden header and the scene follow the world."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest

from crslab import crs
from crslab.plant.model import load_model
from crslab.plant.model_files import REST_MOTOR_RAD, SCENE_XML
from crslab.world.layout import (
    FREE_AIR,
    WORLD_NAMES,
    WorldError,
    arm_points_m,
    load_world,
    peg_depth_m,
    world_file,
)
from crslab.world.scene import load_scene, scene_xml, set_arm_pose

CONTEST_TEXT = world_file("contest")[0].read_text()


def write(tmp_path: Path, text: str, name: str = "bench.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def error_of(path: Path) -> str:
    with pytest.raises(WorldError) as info:
        load_world(path)
    text = str(info.value)
    assert "\n" not in text
    return text


def line_of(text: str, start: str) -> int:
    return next(i for i, line in enumerate(text.splitlines(), 1) if line.startswith(start))


def test_the_builtin_worlds_load_and_none_is_free_air():
    assert WORLD_NAMES == ("none", "contest")
    assert load_world("none") == FREE_AIR and FREE_AIR.is_free_air
    w = load_world("contest")
    assert w.fixtures() == ("table", "hole", "obstacle", "groove", "egg")
    # the positions are the middles of the teams' ranges (docs/worlds.md)
    assert w.hole.center_xy_m == (0.034, 0.35) and w.egg.center_xy_m == (0.226, 0.184)
    assert w.groove.corners_xy_m[0] == (0.386, 0.102) and w.contest.band_g == (500.0, 1000.0)


def test_an_unknown_key_a_wrong_type_and_a_missing_key_each_name_file_line_and_key(tmp_path):
    text = CONTEST_TEXT.replace("depth_m = 0.055", "depht_m = 0.055")
    path = write(tmp_path, text)
    assert error_of(path) == (
        f"{path}:{line_of(text, 'depht_m')}: hole.depht_m: unknown key (allowed: "
        "center_xy_m, top_z_m, diameter_m, depth_m, chamfer_m, block_size_m)"
    )
    text = CONTEST_TEXT.replace("breaking_force_n = 20.0", 'breaking_force_n = "strong"')
    path = write(tmp_path, text)
    assert error_of(path) == (
        f"{path}:{line_of(text, 'breaking_force_n')}: egg.breaking_force_n: must be a number, got 'strong'"
    )
    text = CONTEST_TEXT.replace("width_m = 0.016", "")
    path = write(tmp_path, text)
    assert error_of(path) == f"{path}:{line_of(text, '[groove]')}: groove.width_m: missing"
    text = CONTEST_TEXT.replace("center_m = [0.20, 0.11, 0.15]", "center_m = [0.20, 0.11]")
    path = write(tmp_path, text)
    assert error_of(path).startswith(
        f"{path}:{line_of(text, 'center_m')}: obstacle.center_m: must be a list of 3"
    )
    path = write(tmp_path, CONTEST_TEXT + "[egs]\nx = 1\n")
    assert error_of(path).startswith(f"{path}:{len(CONTEST_TEXT.splitlines()) + 1}: egs: unknown key")
    path = write(tmp_path, "name = 'w'\n[hole\n")
    assert error_of(path).startswith(f"{path}:2: not valid TOML")
    with pytest.raises(WorldError, match=r"^nowhere\.toml: no such world file or built-in world"):
        load_world("nowhere.toml")


def test_sizes_that_cannot_work_together_are_refused(tmp_path):
    text = CONTEST_TEXT.replace("diameter_m = 0.014", "diameter_m = 0.009")
    path = write(tmp_path, text)
    assert error_of(path) == (
        f"{path}:{line_of(text, 'diameter_m = 0.009')}: hole.diameter_m: 0.009 m is not "
        "wider than the peg (0.01 m)"
    )
    text = CONTEST_TEXT.replace("breaking_force_n = 20.0", "breaking_force_n = -1")
    assert "must be > 0" in error_of(write(tmp_path, text))
    text = CONTEST_TEXT.replace("band_g = [500.0, 1000.0]", "band_g = [1000.0, 500.0]")
    assert "contest.band_g: must be [low, high] with low < high" in error_of(write(tmp_path, text))


def test_each_table_reads_its_keys_with_the_fixtures_defaults_and_checks():
    from crslab.world.layout import Contact, parse_world

    w = parse_world('[peg]\ndiameter_m = 0.01\nlength_m = 0.1\nmass_kg = 0.05\n'
                    '[contact]\nfriction = 0.7\n', "w.toml")
    assert w.peg.tip_offset_m == (0.0, 0.0, 0.0)  # left out: the field's own default
    assert w.contact == Contact(friction=0.7, rigid_timeconst_s=0.004, rigid_impedance=0.99,
                                egg_damping_ratio=1.0)
    with pytest.raises(WorldError, match=r"^w.toml:2: contact.rigid_impedance: must be below 1"):
        parse_world("[contact]\nrigid_impedance = 1.0\n", "w.toml")
    with pytest.raises(WorldError, match=r"^w.toml:3: peg.length_m: 0.01 m is not longer than the peg"):
        parse_world("[peg]\ndiameter_m = 0.01\nlength_m = 0.01\nmass_kg = 0.05\n", "w.toml")
    with pytest.raises(WorldError, match=r"^w.toml:2: obstacle.center_m: must be a list of 3 numbers"):
        parse_world("[obstacle]\ncenter_m = [0.1, 0.2]\nsize_m = [0.1, 0.1, 0.1]\n", "w.toml")
    with pytest.raises(WorldError, match=r"^w.toml:2: table.size_m: must be 3 numbers > 0"):
        parse_world("[table]\nsize_m = [1.0, 0.0, 1.0]\ntop_z_m = 0.0\n", "w.toml")


def test_a_fixture_in_the_arms_way_at_rest_is_refused_with_what_and_where(tmp_path):
    elbow = arm_points_m(REST_MOTOR_RAD)["elbow"]
    assert elbow[0] < 0  # at rest the upper arm leans back: the elbow is behind the base
    # a block hung where the forearm rests, 2 cm short of the end effector
    ee = arm_points_m(REST_MOTOR_RAD)["ee"]
    text = CONTEST_TEXT.replace(
        "center_m = [0.20, 0.11, 0.15]", f"center_m = [{ee[0] - 0.02:.3f}, 0.0, {ee[2]:.3f}]"
    ).replace("size_m = [0.04, 0.04, 0.30]", "size_m = [0.02, 0.02, 0.02]")
    path = write(tmp_path, text)
    message = error_of(path)
    assert message.startswith(f"{path}:{line_of(text, '[obstacle]')}: obstacle: the obstacle (x 0.")
    assert "overlaps the arm's forearm at its resting pose (near (" in message
    # the same post is fine when the arm rests elsewhere (its resting pose is a run option)
    assert load_world(path, rest_motor_rad=(np.pi / 2, -0.42, 0.24)).obstacle is not None


def test_a_fixture_out_of_reach_is_refused_with_what_and_where(tmp_path):
    text = CONTEST_TEXT.replace("center_xy_m = [0.226, 0.184]", "center_xy_m = [0.55, 0.184]")
    path = write(tmp_path, text)
    assert error_of(path) == (
        f"{path}:{line_of(text, '[egg]')}: egg: the egg's top at (0.550, 0.184, 0.297) m "
        "is out of the arm's reach (out of reach (farther than 20 in from the shoulder))"
    )
    # reachable by the arm's length but below the framework's safety envelope's floor (4 in)
    text = (
        CONTEST_TEXT.replace("top_z_m = 0.16", "top_z_m = 0.10")
        .replace("block_size_m = [0.08, 0.08, 0.16]", "block_size_m = [0.08, 0.08, 0.10]")
        .replace("depth_m = 0.055", "depth_m = 0.02")
    )
    message = error_of(write(tmp_path, text))
    assert (
        "hole: the hole's mouth at (0.034, 0.350, 0.100) m is out of the arm's reach (outside the "
        "framework's safety envelope)" in message
    )
    assert bool(crs.outside_envelope(crs.ik(np.array([0.034, 0.35, 0.10]) / crs.M_PER_IN)))


def test_fixtures_that_overlap_each_other_are_refused(tmp_path):
    text = CONTEST_TEXT.replace("center_m = [0.20, 0.11, 0.15]", "center_m = [0.226, 0.184, 0.15]")
    message = error_of(write(tmp_path, text))
    assert "overlaps the obstacle" in message and message.split(": ")[1].startswith("egg")


def test_world_none_is_the_arms_own_scene_bit_for_bit():
    assert scene_xml(FREE_AIR) == SCENE_XML.read_text()
    a, b = load_scene(FREE_AIR), load_model()
    assert a.nq == b.nq == 3 and a.ngeom == b.ngeom
    da, db = mujoco.MjData(a), mujoco.MjData(b)
    for data in (da, db):
        data.qpos[:] = (0.1, -1.9, 2.2)
        data.ctrl[:] = (0.5, -1.0, 0.7)
    for _ in range(200):
        mujoco.mj_step(a, da)
        mujoco.mj_step(b, db)
    assert da.qpos.tobytes() == db.qpos.tobytes()


def test_the_contest_scene_holds_the_world_it_was_made_from():
    w = load_world("contest")
    m = load_scene(w)
    d = mujoco.MjData(m)
    dh = crs.ik_dh(np.array([*w.hole.center_xy_m, 0.2]) / crs.M_PER_IN)
    set_arm_pose(m, d, dh)
    mujoco.mj_forward(m, d)
    tip = d.site("peg_tip").xpos
    assert np.allclose(tip, [*w.hole.center_xy_m, 0.2], atol=1e-9)  # the tip is the FK point
    top = d.geom("peg").xpos + d.geom("peg").xmat.reshape(3, 3)[:, 2] * 0  # the capsule's centre
    axis = d.geom("peg").xmat.reshape(3, 3)[:, 2]
    assert abs(abs(axis[2]) - 1) < 1e-9 and top[2] > tip[2]  # vertical, above the tip
    assert d.ncon == 0  # nothing touches at a hover above the hole
    e = m.geom("egg")
    assert np.allclose(e.size, [w.egg.diameter_m / 2, w.egg.diameter_m / 2, w.egg.height_m / 2])
    assert m.geom("hole_chamfer0") is not None and m.nsensor == 7
    assert peg_depth_m(w, (0.034, 0.35, 0.16 - 0.03)) == pytest.approx(0.03)


def run_crslab(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "crslab", *args], capture_output=True, text=True, cwd=cwd, timeout=600
    )


def test_the_command_line_names_a_bad_world_in_one_line_and_a_golden_records_its_world(tmp_path):
    bad = write(tmp_path, CONTEST_TEXT.replace("friction = 0.4", "friction = true"))
    r = run_crslab("sim", "--world", str(bad), "--duration", "0.1", "--no-stdin", cwd=tmp_path)
    assert r.returncode == 2 and r.stdout == ""
    assert (
        r.stderr.strip()
        .splitlines()[-1]
        .endswith(
            f"{bad}:{line_of(bad.read_text(), 'friction =')}: contact.friction: must be a number, got True"
        )
    )
    assert "Traceback" not in r.stderr
    golden = tmp_path / "g.txt"
    r = run_crslab(
        "record",
        "--world",
        "contest",
        "--scenario",
        "hands_off",
        "--duration",
        "4.6",
        "-o",
        str(golden),
        cwd=tmp_path,
    )
    assert r.returncode == 0, r.stderr
    assert "# world: contest\n" in golden.read_text()
    r = run_crslab("check", "--golden", str(golden), cwd=tmp_path)  # the golden's world, not none
    assert r.returncode == 0, r.stdout + r.stderr
