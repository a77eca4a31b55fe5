"""``crslab robots / fk ROBOT / ik ROBOT / workspace / rot`` as a user runs them (subprocesses)."""

import json
import subprocess
import sys

import numpy as np
import pytest


def crslab(*args):
    return subprocess.run([sys.executable, "-m", "crslab", *args], capture_output=True, text=True,
                          timeout=120)


def run_json(*args):
    r = crslab(*args, "--json")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def test_robots_lists_every_robot():
    r = crslab("robots")
    assert r.returncode == 0
    for name in ("crs", "planar3r", "arm7r", "panda", "panda_mdh", "rrr"):
        assert f"\n{name} " in r.stdout
    rows = run_json("robots")
    assert {row["name"]: row["ik"] for row in rows}["rrr"] == "spatial_rrr"


def test_fk_panda_seed_002_in_degrees():
    out = run_json("fk", "panda", "0", "0", "0", "-90", "0", "90", "45")
    np.testing.assert_allclose(out["position"], [0.5545, 0, 0.5215], atol=1e-12)
    np.testing.assert_allclose(out["rotation"], np.diag([1, -1, -1]), atol=1e-12)
    np.testing.assert_allclose(out["joint_centres"][5], [0.4665, 0.015, 0.7315], atol=1e-12)
    text = crslab("fk", "panda", "0", "0", "0", "-90", "0", "90", "45").stdout
    assert "position (m)" in text and "joint centres" in text


def test_fk_radians_and_the_crs_default():
    out = run_json("fk", "rrr", "0.15", "0.29", "0.57", "--rad")
    assert [round(out["position"][0], 2), round(out["position"][1], 3)] == [17.85, 2.698]
    crs = run_json("fk", "0", "0", "0")   # no robot: the CRS arm, DH angles
    np.testing.assert_allclose(crs["position"], [20, 0, 10], atol=1e-12)
    np.testing.assert_allclose(crs["motor_deg"], [0, 90, 0], atol=1e-12)


def test_ik_robots_round_trip_through_fk():
    rrr = run_json("ik", "rrr", "12", "-7", "3")
    ok = [s for s in rrr["solutions"] if s["status"] == "ok"]
    assert len(ok) >= 1  # the other elbow needs |q2| > 90 deg here, beyond its limit
    for s in ok:
        back = run_json("fk", "rrr", *map(str, s["q_deg"]))
        np.testing.assert_allclose(back["position"], [12, -7, 3], atol=1e-9)
    planar = run_json("ik", "planar3r", "1", "1.5", "90")
    np.testing.assert_allclose(planar["solutions"][0]["q_deg"], [0, 90, 0], atol=1e-9)
    pose = run_json("ik", "panda", "0.4", "0.2", "0.5", "0", "0", "180", "--tol", "1e-9")  # Rx(180 deg)
    assert pose["success"] and pose["residual"] <= 1e-9
    back = run_json("fk", "panda", *map(str, pose["q_deg"]))
    np.testing.assert_allclose(back["position"], [0.4, 0.2, 0.5], atol=1e-9)
    np.testing.assert_allclose(back["rotation"], np.diag([1, -1, -1]), atol=1e-8)


def test_ik_crs_robot_form_is_the_crs_shortcut():
    assert run_json("ik", "crs", "10", "0", "20") == run_json("ik", "10", "0", "20")


@pytest.mark.parametrize("args, fragment", [
    (("ik", "rrr", "40", "0", "0"), "no solution for rrr: out of reach"),
    (("ik", "panda", "3", "0", "0", "--restarts", "2"), "no solution within tolerance"),
    (("fk", "panda", "1", "2"), "panda has 7 joints; got 2"),
    (("fk", "r2d2", "1"), "no robot named 'r2d2'"),
    (("ik", "planar3r", "1", "1"), "X Y PHI"),
    (("fk", "planar3r", "0", "0", "0", "--param", "a9=1"), "no parameter 'a9'"),
    (("rot", "--matrix", "1", "0", "0", "0", "1", "0", "0", "0", "-1"), "reflection"),
    (("rot", "--axis-angle", "0", "0", "0", "30"), "non-zero"),
    (("workspace", "panda", "-o", "x.jpg"), ".png"),
])
def test_errors_are_one_line_status_2(args, fragment):
    r = crslab(*args)
    assert r.returncode == 2, r.stdout + r.stderr
    assert r.stdout == "" and r.stderr.count("\n") == 1 and fragment in r.stderr, r.stderr


def test_rot_converts_all_three_ways():
    e = run_json("rot", "--euler-zyx", "30", "20", "10")
    a = run_json("rot", "--axis-angle", *map(str, e["axis"]), str(e["angle_deg"]))
    m = run_json("rot", "--matrix", *map(str, np.ravel(e["matrix"])))
    np.testing.assert_allclose(a["matrix"], e["matrix"], atol=1e-12)
    np.testing.assert_allclose(m["euler_zyx_deg"], [30, 20, 10], atol=1e-9)
    lock = run_json("rot", "--euler-zyx", "30", "90", "10")
    assert lock["euler_singular"] and lock["euler_zyx_deg"][0] == 0


def test_workspace_writes_a_png(tmp_path):
    out = tmp_path / "ws.png"
    r = crslab("workspace", "planar3r", "-o", str(out), "--samples", "3000", "--dextrous")
    assert r.returncode == 0, r.stderr
    assert out.read_bytes()[:4] == b"\x89PNG" and "wrote" in r.stdout
