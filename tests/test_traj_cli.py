"""``crslab traj`` as a user runs it (a real subprocess, so exit codes and streams are real)."""

import subprocess
import sys

import numpy as np
import pytest

from crslab import crs

SQUARE = "# four corners\nx_in,y_in,z_in,t_s\n10,0,20,0\n12,-3,16,1.5\n12,3,16,2.5\n10,0,20,4\n"


def crslab(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=120, cwd=cwd)


def test_traj_writes_a_1khz_csv_and_a_png(tmp_path):
    pts = tmp_path / "pts.csv"
    pts.write_text(SQUARE)
    out, png = tmp_path / "traj.csv", tmp_path / "traj.png"
    r = crslab("traj", "crs", "--waypoints", pts, "--profile", "li", "-o", out, "--plot", png)
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    header = out.read_text().splitlines()[0].split(",")
    assert header == ["t_s", "q1_rad", "q2_rad", "q3_rad", "qd1_rad_s", "qd2_rad_s", "qd3_rad_s",
                      "qdd1_rad_s2", "qdd2_rad_s2", "qdd3_rad_s2", "jerk1_rad_s3", "jerk2_rad_s3",
                      "jerk3_rad_s3"]
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    t, q, qd, qdd, jerk = table[:, 0], table[:, 1:4], table[:, 4:7], table[:, 7:10], table[:, 10:13]
    np.testing.assert_array_equal(t, np.arange(4001) / 1000)  # 0 to 4 s, every millisecond
    # at each row's time the arm is at rest on that row's point (FK of the written angles)
    rows = [0, 1500, 2500, 4000]
    np.testing.assert_allclose(crs.fk(q[rows]), [[10, 0, 20], [12, -3, 16], [12, 3, 16], [10, 0, 20]],
                               atol=1e-9)
    assert np.abs(qd[rows]).max() < 1e-9 and np.abs(qdd[rows]).max() < 1e-6
    assert np.abs(jerk[rows]).max() < 1e-3  # Li: zero jerk at both ends of every segment
    # the written columns are each other's derivatives (central differences at 1 ms)
    np.testing.assert_allclose((q[2:] - q[:-2]) / 0.002, qd[1:-1], atol=2e-5)
    np.testing.assert_allclose((qd[2:] - qd[:-2]) / 0.002, qdd[1:-1], atol=2e-3)
    png_bytes = png.read_bytes()
    assert png_bytes[:8] == b"\x89PNG\r\n\x1a\n" and len(png_bytes) > 20_000
    assert "li profile through 4 waypoints" in r.stdout and "4001 rows at 1000 Hz" in r.stdout


@pytest.mark.parametrize("profile", ["quintic", "cubic", "trapezoid"])
def test_every_profile_reaches_the_points(tmp_path, profile):
    pts = tmp_path / "pts.csv"
    pts.write_text("x_in,y_in,z_in\n10,0,20\n12,-3,16\n")
    out = tmp_path / "t.csv"
    r = crslab("traj", "crs", "--waypoints", pts, "--profile", profile, "-o", out, "--vmax", "0.5")
    assert r.returncode == 0, r.stderr
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(crs.fk(table[-1, 1:4]), [12, -3, 16], atol=1e-9)
    assert np.abs(table[:, 4:7]).max() <= 0.5 * (1 + 1e-9)  # the speed limit holds


def test_an_unreachable_row_is_one_line_naming_file_and_line_with_status_2(tmp_path):
    pts = tmp_path / "pts.csv"
    pts.write_text("x_in,y_in,z_in\n10,0,20\n12,0,16\n0,0,31\n")
    r = crslab("traj", "crs", "--waypoints", "pts.csv", "-o", "out.csv", cwd=tmp_path)
    assert r.returncode == 2
    assert r.stdout == ""
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    assert r.stderr.startswith("crslab traj: pts.csv line 4: waypoint (0, 0, 31) in is out of reach")
    assert not (tmp_path / "out.csv").exists()


@pytest.mark.parametrize("args, words", [
    (["--waypoints", "nope.csv", "-o", "o.csv"], "nope.csv: no such file"),
    (["--waypoints", "pts.csv", "-o", "o.csv", "--vmax", "-1"], "--vmax must be a finite number >= 0"),
    (["--waypoints", "pts.csv", "-o", "o.csv", "--vmax", "0"], "give a duration or a speed limit"),
    (["--waypoints", "pts.csv", "-o", "pts.csv/o.csv"], "cannot write pts.csv/o.csv"),  # a file as a folder
    (["--waypoints", "pts.csv", "-o", "o.csv", "--profile", "sine"], "invalid choice: 'sine'"),
])
def test_user_errors_are_one_line_with_status_2(tmp_path, args, words):
    (tmp_path / "pts.csv").write_text("x_in,y_in,z_in\n10,0,20\n12,0,16\n")
    r = crslab("traj", "crs", *args, cwd=tmp_path)
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    assert words in r.stderr


def test_an_unknown_robot_is_a_usage_error(tmp_path):
    r = crslab("traj", "puma", "--waypoints", "p.csv", "-o", "o.csv", cwd=tmp_path)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "invalid choice: 'puma'" in r.stderr


def test_traj_plans_for_the_rrr_arm_in_its_own_length_unit(tmp_path):
    from crslab.robots import load

    (tmp_path / "rrr.csv").write_text("x_units,y_units,z_units,t_s\n17.85,2.698,5.219,0\n12,0,-3,3.5\n")
    r = crslab("traj", "rrr", "--waypoints", "rrr.csv", "--profile", "cubic", "-o", "o.csv", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    table = np.loadtxt(tmp_path / "o.csv", delimiter=",", skiprows=1)
    assert table.shape == (3501, 13)
    ends = load("rrr").fk(table[[0, -1], 1:4])[:, :3, 3]
    np.testing.assert_allclose(ends, [[17.85, 2.698, 5.219], [12, 0, -3]], atol=1e-9)
    (tmp_path / "crs.csv").write_text("x_in,y_in,z_in\n10,0,20\n12,0,16\n")
    wrong_unit = crslab("traj", "rrr", "--waypoints", "crs.csv", "-o", "o.csv", cwd=tmp_path)
    assert wrong_unit.returncode == 2 and wrong_unit.stderr.count("\n") == 1
    assert "crs.csv line 1: the header must name the columns x_units, y_units, z_units" in wrong_unit.stderr


def test_the_traj_plot_draws_the_written_columns(tmp_path, drawn_figures):
    """The plot's four panels draw each joint's position, velocity, acceleration and jerk as the
    CSV holds them, and mark every waypoint's arrival."""
    from crslab.cli import main

    pts, out = tmp_path / "pts.csv", tmp_path / "traj.csv"
    pts.write_text(SQUARE)
    png = tmp_path / "t.png"
    assert main(["traj", "crs", "--waypoints", str(pts), "-o", str(out), "--plot", str(png)]) == 0
    [fig] = drawn_figures
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    assert len(fig.axes) == 4
    for panel, ax in enumerate(fig.axes):
        curves = [line for line in ax.lines if len(line.get_xdata()) > 2]
        assert [line.get_label() for line in curves] == ["motor angle 1", "motor angle 2", "motor angle 3"]
        for j, line in enumerate(curves):
            np.testing.assert_allclose(line.get_xdata(), table[:, 0], atol=1e-12)
            np.testing.assert_allclose(line.get_ydata(), table[:, 1 + 3 * panel + j], rtol=1e-9, atol=1e-9)
        marks = sorted(line.get_xdata()[0] for line in ax.lines if len(line.get_xdata()) == 2)
        assert marks == [0.0, 1.5, 2.5, 4.0]
