"""Seeing the world: a run in the contest world draws its fixtures and the peg in the rerun
recording and scopes the forces the arm presses on them (the egg's included) and the scale's
grams; the CSV holds the same world columns; the MuJoCo viewer's scene is the world's; a
free-air run has none of it."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest
from rerun.chunk import RrdReader

from crslab import crs
from crslab.scopes.arm3d import ArmModel
from crslab.scopes.signals import SIGNALS, WORLD_SIGNALS
from crslab.world import load_world

ROOT = Path(__file__).resolve().parents[1]
CONTEST = load_world("contest")


@pytest.fixture(scope="module")
def pressed(tmp_path_factory):
    """crslab's Lab 1 in the contest world while a hand presses the peg down onto the egg until it breaks."""
    tmp = tmp_path_factory.mktemp("world_rrd")
    e = CONTEST.egg
    x, y = (v / crs.M_PER_IN for v in e.center_xy_m)
    above, into = (e.top_z_m + 0.02) / crs.M_PER_IN, (e.top_z_m - 0.004) / crs.M_PER_IN
    scenario = tmp / "press.toml"
    scenario.write_text(
        "end = 4.0\n"
        f'[[event]]\nat = 0.2\nkind = "hand"\nxyz_in = [{x:.5f}, {y:.5f}, {above:.5f}]\nduration = 1.5\n'
        f'[[event]]\nat = 2.0\nkind = "hand"\nxyz_in = [{x:.5f}, {y:.5f}, {into:.5f}]\nduration = 1.5\n'
    )
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "crslab",
            "sim",
            "--fast",
            "--no-stdin",
            "--world",
            "contest",
            "--scenario",
            str(scenario),
            "--rrd",
            str(tmp / "run.rrd"),
            "--csv",
            str(tmp / "run.csv"),
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stderr
    entities = {}
    for chunk in RrdReader(tmp / "run.rrd").stream():
        key = chunk.entity_path + (" static" if chunk.is_static else "")
        entities.setdefault(key, []).append(pa.Table.from_batches([chunk.to_record_batch()]))
    return tmp, {k: pa.concat_tables(t, promote_options="default") for k, t in entities.items()}


def test_the_recording_draws_the_fixtures_and_the_peg(pressed):
    _, entities = pressed
    for entity in (
        "/arm/peg/shapes/capsule static",
        "/arm/hole/shapes/box static",
        "/arm/obstacle/shapes/box static",
        "/arm/groove/shapes/box static",
        "/arm/egg/shapes/ellipsoid static",
        "/arm/scale/shapes/cylinder static",
        "/arm/peg",
    ):
        assert entity in entities, sorted(entities)
    half = entities["/arm/egg/shapes/ellipsoid static"]["Ellipsoids3D:half_sizes"].to_pylist()
    assert np.allclose(
        half, [[[CONTEST.egg.diameter_m / 2, CONTEST.egg.diameter_m / 2, CONTEST.egg.height_m / 2]]]
    )
    # the collision capsules of the arm's links are not drawn (only the visual ones)
    labels = entities["/arm/forearm/shapes/capsule static"]["Capsules3D:labels"].to_pylist()
    assert labels == [["forearm_link"]]


def test_the_egg_force_and_the_scale_are_scopes(pressed):
    tmp, entities = pressed
    names = entities["/scopes/world static"]["SeriesLines:names"].to_pylist()
    assert names == [
        ["egg_force", "egg_force_xyz_x", "egg_force_xyz_y", "egg_force_xyz_z", "hole_force", "obstacle_force",
         "obstacle_peg_force", "obstacle_forearm_force", "obstacle_upper_arm_force", "groove_force",
         "groove_side_force", "table_force"]
    ]
    forces = np.array([v for v in entities["/scopes/world"]["Scalars:scalars"].to_pylist()], dtype=object)
    egg = np.concatenate([np.asarray(row, float).reshape(-1, 12)[:, 0] for row in forces])
    assert egg.max() > CONTEST.egg.breaking_force_n  # pressed until it broke
    header = (tmp / "run.csv").read_text().splitlines()[0].split(",")
    assert header[-len(WORLD_SIGNALS) :] == [s.csv_name for s in WORLD_SIGNALS]
    data = np.loadtxt(tmp / "run.csv", delimiter=",", skiprows=1)
    column = {name: i for i, name in enumerate(header)}
    broken = data[:, column["egg_broken [0/1]"]]
    assert broken[-1] == 1 and broken[0] == 0
    assert data[:, column["egg_force [N]"]].max() == pytest.approx(egg.max())


def test_a_free_air_run_has_no_world_columns(tmp_path):
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "crslab",
            "sim",
            "--fast",
            "--no-stdin",
            "--duration",
            "0.2",
            "--csv",
            str(tmp_path / "run.csv"),
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stderr
    header = (tmp_path / "run.csv").read_text().splitlines()[0].split(",")
    assert header == ["tick", "t [s]", *(s.csv_name for s in SIGNALS)]


def test_the_viewer_and_the_3d_views_draw_the_worlds_scene():
    arm = ArmModel(CONTEST)
    pos, _ = arm.poses(np.array([[0.0, 0.0, 0.0]]))
    peg = arm.body_index("peg")
    # the peg's wrist at the forearm's end, DH zero: the arm stands 10 cm higher, its tip at the FK point
    assert np.allclose(pos[0, peg], [0.508, 0.0, 0.254 + CONTEST.arm_raised_m])
    assert np.allclose(pos[0, arm.body_index("hole")], [*CONTEST.hole.center_xy_m, 0.0])
    assert [b.name for b in ArmModel().moving] == ["waist", "upper_arm", "forearm"]
