"""World files (crslab/world/world_file.py, layout_checks.py): the built-ins load, a bad file is
one line naming file, line and key, a fixture in the arm's way at rest or out of its reach is
refused with what and where, and the command line, the golden header and the scene follow the
world. The contest world as the bench is built: every team's commanded points where the fixtures
let them be, every layout of the teams' spreads admitted."""

from __future__ import annotations

import itertools
import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest

from crslab import crs
from crslab.plant.model import load_model
from crslab.plant.model_files import REST_MOTOR_RAD, SCENE_XML
from crslab.world import FREE_AIR, WORLD_NAMES, WorldError, load_world, world_file
from crslab.world.fixtures import Contact, ContestRules
from crslab.world.layout_checks import arm_points_m
from crslab.world.scene import load_scene, scene_xml, set_arm_pose
from crslab.world.world_file import parse_world

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


def swap(text: str, old: str, new: str) -> str:
    """``text`` with ``old`` (once in it: the test breaks loudly when contest.toml changes) as ``new``."""
    assert text.count(old) == 1, old
    return text.replace(old, new)


def test_the_builtin_worlds_load_and_none_is_free_air():
    assert WORLD_NAMES == ("none", "contest")
    assert load_world("none") == FREE_AIR and FREE_AIR.is_free_air
    w = load_world("contest")
    assert w.fixtures() == ("table", "hole", "obstacle", "groove", "egg")
    # the positions are the middles of the teams' ranges (docs/worlds.md)
    assert w.hole.center_xy_m == (0.034, 0.35) and w.egg.center_xy_m == (0.226, 0.184)
    assert w.groove.corners_xy_m[0] == (0.386, 0.102) and w.contest.band_g == (500.0, 1000.0)
    assert w.contest == ContestRules()  # contest.toml writes out crslab's own rules


def test_an_unknown_key_a_wrong_type_and_a_missing_key_each_name_file_line_and_key(tmp_path):
    text = swap(CONTEST_TEXT, "depth_m = 0.062", "depht_m = 0.062")
    path = write(tmp_path, text)
    assert error_of(path) == (
        f"{path}:{line_of(text, 'depht_m')}: hole.depht_m: unknown key (allowed: "
        "block_size_xy_m, center_xy_m, chamfer_m, depth_m, diameter_m, top_z_m)"
    )
    text = swap(CONTEST_TEXT, "breaking_force_n = 25.0", 'breaking_force_n = "strong"')
    path = write(tmp_path, text)
    assert error_of(path) == (
        f"{path}:{line_of(text, 'breaking_force_n')}: egg.breaking_force_n: must be a number, got 'strong'"
    )
    text = swap(CONTEST_TEXT, "width_m = 0.016", "")
    path = write(tmp_path, text)
    assert error_of(path) == f"{path}:{line_of(text, '[groove]')}: groove.width_m: missing"
    text = swap(CONTEST_TEXT, "center_xy_m = [0.20, 0.11]", "center_xy_m = [0.20, 0.11, 0.15]")
    path = write(tmp_path, text)
    assert error_of(path).startswith(
        f"{path}:{line_of(text, 'center_xy_m = [0.20')}: obstacle.center_xy_m: must be a list of 2"
    )
    path = write(tmp_path, CONTEST_TEXT + "[egs]\nx = 1\n")
    assert error_of(path).startswith(f"{path}:{len(CONTEST_TEXT.splitlines()) + 1}: egs: unknown key")
    path = write(tmp_path, "name = 'w'\n[hole\n")
    assert error_of(path).startswith(f"{path}:2: not valid TOML")
    with pytest.raises(WorldError, match=r"^nowhere\.toml: no such world file or built-in world"):
        load_world("nowhere.toml")


@pytest.mark.parametrize(
    "old, new, says",
    [
        (
            "diameter_m = 0.014",
            "diameter_m = 0.009",
            "hole.diameter_m: 0.009 m is not wider than the peg (0.01 m)",
        ),
        ("breaking_force_n = 25.0", "breaking_force_n = -1", "egg.breaking_force_n: must be > 0, got -1"),
        ("mass_kg = 0.030", "mass_kg = 1e-300", "peg.mass_kg: 1e-300 is too small a number"),
        (
            "band_g = [500.0, 1000.0]",
            "band_g = [1000.0, 500.0]",
            "contest.band_g: must be [low, high] with low < high",
        ),
        (
            "hold_tolerance_s = 0.2",
            "hold_tolerance_s = 2.5",
            "contest.hold_tolerance_s: 2.5 s is not shorter than the hold (2 s)",
        ),
        (
            "peg_hold_s = 0.5",
            "peg_hold_s = 0.2",
            "contest.peg_hold_s: 0.2 s is not longer than hold_tolerance_s (0.2 s)",
        ),
        (
            "obstacle_around = true",
            "obstacle_around = 1",
            "contest.obstacle_around: must be true or false, got 1",
        ),
        (
            "wrist_above_tip_m = 0.10",
            "wrist_above_tip_m = 0.08",
            "peg.wrist_above_tip_m: 0.08 m leaves the forearm (32 mm round its axis) lower than the peg",
        ),
        (
            "depth_m = 0.030",
            "depth_m = 0.045",
            "groove.depth_m: 0.045 m is not shallower than the plate is thick",
        ),
        (
            "scale_diameter_m = 0.076",
            "scale_diameter_m = 0.04",
            "egg.scale_diameter_m: 0.04 m is not wider than the egg",
        ),
        ("top_z_m = 0.30", "top_z_m = 0.09", "obstacle.top_z_m: 0.09 m is not above the table (0.1 m)"),
    ],
)
def test_sizes_that_cannot_work_together_are_refused_at_their_line(tmp_path, old, new, says):
    text = swap(CONTEST_TEXT, old, new)
    path = write(tmp_path, text)
    assert error_of(path).startswith(f"{path}:{line_of(text, new)}: {says}")


def test_a_groove_that_folds_over_itself_is_refused(tmp_path):
    text = swap(CONTEST_TEXT, "[0.325, 0.0325],  # second corner", "[0.43, 0.08],     # second corner")
    message = error_of(write(tmp_path, text))
    assert (
        "groove.corners_xy_m: the centre line turns 168 degrees at corner 2 (at most 150): the channel would "
        "fold over itself" in message
    )


def test_each_table_reads_its_keys_with_the_fixtures_defaults_and_checks():
    w = parse_world(
        "[peg]\ndiameter_m = 0.01\nlength_m = 0.05\nmass_kg = 0.05\nwrist_above_tip_m = 0.1\n"
        "[contact]\nfriction = 0.7\n",
        "w.toml",
    )
    assert w.peg.gripper_diameter_m == 0.024  # left out: the field's own default
    assert w.contact == Contact(
        friction=0.7, rigid_timeconst_s=0.004, rigid_impedance=0.99, egg_damping_ratio=0.2
    )
    assert w.contest == ContestRules() and w.arm_raised_m == 0.1
    with pytest.raises(
        WorldError, match=r"^w.toml:2: contact.rigid_impedance: must be at most 0.9999, got 1.0"
    ):
        parse_world("[contact]\nrigid_impedance = 1.0\n", "w.toml")
    with pytest.raises(WorldError, match=r"^w.toml:3: peg.length_m: 0.01 m is not longer than the peg"):
        parse_world(
            "[peg]\ndiameter_m = 0.01\nlength_m = 0.01\nmass_kg = 0.05\nwrist_above_tip_m = 0.1\n", "w.toml"
        )
    with pytest.raises(WorldError, match=r"^w.toml:2: table.size_m: must be > 0, got"):
        parse_world("[table]\nsize_m = [1.0, 0.0, 1.0]\ntop_z_m = 0.0\n", "w.toml")
    with pytest.raises(WorldError, match=r"^w.toml:1: hole: needs a \[peg\] table"):
        parse_world(
            "[hole]\ncenter_xy_m = [0.03, 0.35]\ntop_z_m = 0.17\ndiameter_m = 0.014\n"
            "depth_m = 0.05\nchamfer_m = 0.004\nblock_size_xy_m = [0.08, 0.08]\n",
            "w.toml",
        )


def test_a_fixture_in_the_arms_way_at_rest_is_refused_with_what_and_where(tmp_path):
    w = load_world("contest")
    p = arm_points_m(w, REST_MOTOR_RAD)
    assert p["elbow"][0] < 0  # at rest the upper arm leans back: the elbow is behind the base
    # a post under the forearm at rest, its top 2 cm above the forearm's axis 3 cm from the wrist
    x = p["wrist"][0] - 0.03
    top = p["wrist"][2] + 0.02
    text = swap(
        swap(CONTEST_TEXT, "center_xy_m = [0.20, 0.11]", f"center_xy_m = [{x:.3f}, 0.0]"),
        "top_z_m = 0.30",
        f"top_z_m = {top:.3f}",
    )
    path = write(tmp_path, text)
    message = error_of(path)
    assert message.startswith(f"{path}:{line_of(text, '[obstacle]')}: obstacle: the obstacle (x 0.")
    assert "overlaps the arm's forearm at its resting pose (near (" in message
    # the same post is fine when the arm rests elsewhere (its resting pose is a run option)
    assert load_world(path, rest_motor_rad=(np.pi / 2, -0.42, 0.24)).obstacle is not None
    # a rest that puts the peg's tip into the table (FK: z = 0.254 (1 + cos 1.2 - sin 1.5) = 0.093 m,
    # under its top at 0.10) is refused at the table's line; 1.0 instead of 1.2 puts it at 0.138 m
    contest = world_file("contest")[0]
    into = r"holds the arm's peg at its resting pose \(near \(0.255, 0.000, 0.093\) m\)"
    with pytest.raises(WorldError, match=r"contest.toml:\d+: table: the table \(top at z 0.100 m\) " + into):
        load_world(contest, rest_motor_rad=(0.0, 1.2, 1.5))
    assert load_world(contest, rest_motor_rad=(0.0, 1.0, 1.5)).table is not None


def test_a_fixture_out_of_reach_is_refused_with_what_and_where(tmp_path):
    text = swap(CONTEST_TEXT, "center_xy_m = [0.226, 0.184]", "center_xy_m = [0.55, 0.184]")
    path = write(tmp_path, text)
    assert error_of(path) == (
        f"{path}:{line_of(text, '[egg]')}: egg: the egg's top at (0.550, 0.184, 0.297) m "
        "is out of the arm's reach (out of reach (farther than 20 in from the shoulder))"
    )
    # reachable by the arm's length but below the framework's safety envelope's floor (4 in)
    text = swap(
        swap(CONTEST_TEXT, "top_z_m = 0.17", "top_z_m = 0.10"),
        "top_z_m = 0.10\nsize_m",
        "top_z_m = 0.0\nsize_m",
    )
    text = swap(text, "depth_m = 0.062", "depth_m = 0.02")
    message = error_of(write(tmp_path, text))
    assert (
        "hole: the hole's mouth at (0.034, 0.350, 0.100) m is out of the arm's reach (outside the "
        "framework's safety envelope)" in message
    )
    assert bool(crs.outside_envelope(crs.ik(np.array([0.034, 0.35, 0.10]) / crs.M_PER_IN)))


def test_fixtures_that_overlap_each_other_are_refused(tmp_path):
    text = swap(CONTEST_TEXT, "center_xy_m = [0.20, 0.11]", "center_xy_m = [0.24, 0.16]")
    message = error_of(write(tmp_path, text))
    assert "overlaps the obstacle" in message and message.split(": ")[1].startswith("egg")


# -- the contest world as the bench is built ----------------------------------------------------

# The teams' commanded points (docs/worlds.md; the teams' spreads in the course's 2022-2023 lab).
HOVER_Z, INSERT_Z = (0.18, 0.25), (0.111, 0.150)
PASS_Z = (0.36, 0.40)
GROOVE_Z = (0.205, 0.220)
EGG_CONTACT_Z = (0.29, 0.305)
SPREADS = {  # fixture: ((x low, x high), (y low, y high))
    "hole": ((0.030, 0.041), (0.340, 0.360)),
    "obstacle": ((0.19, 0.21), (0.10, 0.12)),
    "entrance": ((0.373, 0.399), (0.090, 0.114)),
    "corner1": ((0.40, 0.425), (0.035, 0.06)),
    "corner2": ((0.31, 0.34), (0.015, 0.05)),
    "exit": ((0.370, 0.406), (-0.090, -0.043)),
    "egg": ((0.200, 0.252), (0.177, 0.191)),
}


def test_the_contest_heights_hold_every_teams_commanded_points():
    w = load_world("contest")
    h, g, e, o = w.hole, w.groove, w.egg, w.obstacle
    assert h.top_z_m < HOVER_Z[0]  # every hover is above the hole
    assert (
        h.top_z_m - h.depth_m < INSERT_Z[0] and INSERT_Z[1] < h.top_z_m
    )  # every insertion in it, above its floor
    assert h.top_z_m - INSERT_Z[1] >= 0.01  # the shallowest insertion is 1 cm deep or more
    assert w.peg.length_m > h.top_z_m - INSERT_Z[0]  # the deepest: the gripper stays above the block
    assert g.floor_z_m < GROOVE_Z[0] - 0.005 and GROOVE_Z[1] < g.top_z_m  # within the groove, off its floor
    assert o.top_z_m < PASS_Z[0] - 0.05  # passes over it, the arm's sag and the slope down included
    assert EGG_CONTACT_Z[0] <= e.top_z_m <= EGG_CONTACT_Z[1]


def test_nothing_of_the_arm_is_lower_than_the_peg_at_the_teams_points():
    """At every point the teams command (over the hole and in it, over the post, along the groove,
    at the egg), the forearm's collision capsule in the compiled scene is above the peg's top and the
    upper arm's above the tip, wherever either is within 10 cm (in x-y) of the tip: the peg goes in
    first, and a fixture the tip passes over is passed by the arm too."""
    w = load_world("contest")
    m = load_scene(w)
    d = mujoco.MjData(m)
    points = [(*w.hole.center_xy_m, z) for z in (*HOVER_Z, *INSERT_Z)]
    points += [(*w.obstacle.center_xy_m, z) for z in PASS_Z]
    points += [(*c, z) for c in w.groove.corners_xy_m for z in GROOVE_Z]
    points += [(*w.egg.center_xy_m, z) for z in EGG_CONTACT_Z]
    near = 0
    for point in points:
        set_arm_pose(m, d, crs.ik_dh(np.array(point) / crs.M_PER_IN))
        mujoco.mj_kinematics(m, d)
        tip = d.site("peg_tip").xpos.copy()
        assert np.allclose(tip, point, atol=1e-9)  # the tip is the point the lab's kinematics names
        for name, above in (("forearm_link_collision", w.peg.length_m), ("upper_arm_link_collision", 0.0)):
            g, (radius, half) = d.geom(name), m.geom(name).size[:2]
            axis = g.xmat.reshape(3, 3)[:, 2]
            along = g.xpos + np.linspace(-half, half, 201)[:, None] * axis
            close = np.hypot(*(along[:, :2] - tip[:2]).T) < 0.10
            near += int(close.any())
            assert (along[close, 2] - radius > tip[2] + above).all(), (name, point)
    assert near >= len(points)  # the forearm is near the tip at every point (it ends above it)


def layouts() -> list[tuple[str, dict[str, tuple[float, float]]]]:
    """Benches across the teams' spreads: every fixture at each end of its spread together (all low,
    all high), each one alone at its extremes with the rest at the contest's places, and the
    older (2017) layout: the hole at (0.030, 0.325), the egg at (0.352, -0.136) below the Z."""
    w = load_world("contest")
    base = {
        "hole": w.hole.center_xy_m,
        "obstacle": w.obstacle.center_xy_m,
        "egg": w.egg.center_xy_m,
        **dict(zip(("entrance", "corner1", "corner2", "exit"), w.groove.corners_xy_m)),
    }
    out = [
        ("all low", {k: (x[0], y[0]) for k, (x, y) in SPREADS.items()}),
        ("all high", {k: (x[1], y[1]) for k, (x, y) in SPREADS.items()}),
    ]
    for k, (xs, ys) in SPREADS.items():
        for x, y in itertools.product(xs, ys):
            out.append((f"{k} at ({x}, {y})", {**base, k: (x, y)}))
    out.append(("2017", {**base, "hole": (0.030, 0.325), "egg": (0.352, -0.136)}))
    return out


def bench_text(places: dict[str, tuple[float, float]]) -> str:
    w = load_world("contest")
    text = CONTEST_TEXT
    for key, old in (
        ("hole", w.hole.center_xy_m),
        ("obstacle", w.obstacle.center_xy_m),
        ("egg", w.egg.center_xy_m),
    ):
        text = swap(
            text,
            f"center_xy_m = [{old[0]}, {old[1]}]".replace("0.2,", "0.20,").replace(" 0.11]", " 0.11]"),
            f"center_xy_m = [{places[key][0]}, {places[key][1]}]",
        )
    for key, old in zip(("entrance", "corner1", "corner2", "exit"), w.groove.corners_xy_m):
        text = swap(text, f"[{old[0]}, {old[1]}]", f"[{places[key][0]}, {places[key][1]}]")
    return text


@pytest.mark.parametrize("name, places", layouts(), ids=[n for n, _ in layouts()])
def test_every_layout_of_the_teams_spreads_is_admitted(tmp_path, name, places):
    world = load_world(write(tmp_path, bench_text(places)))
    assert world.egg.center_xy_m == places["egg"] and world.groove.corners_xy_m[3] == places["exit"]


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
    axis = d.geom("peg").xmat.reshape(3, 3)[:, 2]
    assert abs(abs(axis[2]) - 1) < 1e-9  # vertical
    # the peg from the tip up to its length, the gripper on to the wrist, the wrist 10 cm above the tip
    for name, low, high in (
        ("peg", 0.0, w.peg.length_m),
        ("gripper", w.peg.length_m, w.peg.wrist_above_tip_m),
    ):
        g, size = d.geom(name), m.geom(name).size
        ends = sorted(g.xpos[2] + s * size[1] * g.xmat.reshape(3, 3)[2, 2] for s in (-1, 1))
        assert ends[0] - size[0] == pytest.approx(tip[2] + low, abs=1e-9)
        assert (
            ends[1] + size[0] == pytest.approx(tip[2] + high, abs=1e-9)
            if name == "peg"
            else ends[1] == pytest.approx(tip[2] + high, abs=1e-9)
        )
    assert np.allclose(d.body("peg").xpos, tip + (0, 0, w.peg.wrist_above_tip_m), atol=1e-9)
    assert d.ncon == 0  # nothing touches at a hover above the hole
    e = m.geom("egg")
    assert np.allclose(e.size, [w.egg.diameter_m / 2, w.egg.diameter_m / 2, w.egg.height_m / 2])
    assert m.geom("hole_chamfer0") is not None
    # the peg tip's position, then a force sensor per fixture body, in C's order
    assert [m.sensor(i).name for i in range(m.nsensor)] == [
        "peg_tip",
        "table_force",
        "hole_force",
        "obstacle_force",
        "obstacle_forearm_force",
        "obstacle_upper_arm_force",
        "groove_force",
        "egg_force",
        "scale_force",
    ]


def run_crslab(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "crslab", *args], capture_output=True, text=True, cwd=cwd, timeout=600
    )


def test_the_command_line_names_a_bad_world_in_one_line_and_a_golden_records_its_world(tmp_path):
    bad = write(tmp_path, swap(CONTEST_TEXT, "friction = 0.4", "friction = true"))
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
