"""``crslab fk`` / ``crslab ik`` as a user runs them (a real subprocess, so exit codes are real)."""

import json
import subprocess
import sys

import pytest


def crslab(*args):
    return subprocess.run([sys.executable, "-m", "crslab", *args], capture_output=True, text=True,
                          timeout=60)


def test_fk_motor_deg_prints_xyz_and_dh():
    r = crslab("fk", "--motor-deg", "0", "90", "0")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert [float(v) for v in lines[0].split()[2:]] == [20.0, 0.0, 10.0]
    assert [float(v) for v in lines[1].split()[2:]] == [0.0, 0.0, 0.0]


@pytest.mark.parametrize("flag, values, xyz", [
    ("--motor-rad", ["0", "0", "-1.5707963267948966"], [0, 0, 30]),
    ("--dh-deg", ["0", "-90", "90"], [10, 0, 20]),
])
def test_fk_json(flag, values, xyz):
    r = crslab("fk", flag, *values, "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["xyz_in"] == pytest.approx(xyz, abs=1e-12)


def test_ik_prints_dh_and_motor_degrees():
    r = crslab("ik", "10", "0", "20", "--json")
    out = json.loads(r.stdout)
    assert out["motor_deg"] == pytest.approx([0, 0, 0], abs=1e-9)
    assert out["dh_deg"] == pytest.approx([0, -90, 90], abs=1e-9)
    down = json.loads(crslab("ik", "10", "0", "20", "--elbow", "down", "--json").stdout)
    assert down["dh_deg"] == pytest.approx([0, 0, -90], abs=1e-9)


def test_ik_unreachable_is_one_line_status_2():
    r = crslab("ik", "0", "0", "31")
    assert r.returncode == 2
    assert r.stdout == ""
    assert r.stderr.count("\n") == 1 and "out of reach" in r.stderr


def test_bad_option_is_one_line_status_2():
    r = crslab("fk", "--motor-deg", "1", "2")
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and "--motor-deg" in r.stderr
