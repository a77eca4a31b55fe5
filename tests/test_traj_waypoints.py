"""Waypoint files: parsing, IK into joint space, timing, and errors that name the file and line."""

import io
import math

import numpy as np
import pytest

from crslab import crs
from crslab.traj.joint_space import crs_outside_envelope, crs_why_outside
from crslab.traj.waypoints import WaypointError, plan_waypoints, read_waypoints


def plan_text(text, name="pts.csv", **kw):
    return plan_waypoints(read_waypoints(io.StringIO(text), name=name), "crs", **kw)


def error_of(text, **kw):
    with pytest.raises(WaypointError) as info:
        plan_text(text, **kw)
    return info.value


# ---- the joint path goes through the points ----

def test_each_row_is_reached_at_its_time_through_elbow_up_ik():
    text = "# a triangle\nx_in,y_in,z_in,t_s\n10,0,20,0\n12,-3,16,2.0\n\n12,3,16,3.5\n10,0,20,6\n"
    plan = plan_text(text)
    assert plan.arrival_s.tolist() == [0.0, 2.0, 3.5, 6.0]
    assert plan.waypoints.lines == [3, 4, 6, 7]
    s = plan.trajectory.evaluate(plan.arrival_s)
    np.testing.assert_allclose(crs.fk(s.q), plan.waypoints.xyz, atol=1e-9)
    np.testing.assert_allclose(s.qd, 0.0, atol=1e-14)  # rest to rest
    dh = crs.motor_to_dh(s.q)
    assert np.all(dh[:, 2] > 0)  # elbow up: th3 DH >= 0


def test_speeds_set_each_segment_from_its_straight_line_length():
    plan = plan_text("x_in,y_in,z_in,speed_in_s\n10,0,20,\n13,4,20,2.5\n13,4,15,1\n", vmax_rad_s=3.0)
    assert plan.trajectory.duration_s == pytest.approx([math.dist((10, 0, 20), (13, 4, 20)) / 2.5, 5.0 / 1.0])


def test_without_times_each_segment_takes_its_slowest_joint_minimum():
    plan = plan_text("x_in,y_in,z_in\n10,0,20\n14,-6,12\n", profile="li", vmax_rad_s=0.8)
    dq = np.abs(crs.ik([14, -6, 12]) - crs.ik([10, 0, 20]))
    # Li without cruise: peak velocity 2L/T, so the slowest joint needs 2 max|dq| / vmax
    assert plan.trajectory.duration_s[0] == pytest.approx(2 * dq.max() / 0.8, rel=1e-12)
    assert np.abs(plan.trajectory.sample()[1].qd).max() == pytest.approx(0.8, rel=1e-5)


def test_an_empty_time_goes_as_fast_as_allowed_and_later_times_count_from_the_start():
    plan = plan_text("x_in,y_in,z_in,t_s\n10,0,20,\n14,-6,12,\n10,0,20,9\n", profile="cubic", vmax_rad_s=0.8)
    dq = np.abs(crs.ik([14, -6, 12]) - crs.ik([10, 0, 20])).max()
    first = 1.5 * dq / 0.8  # cubic peak velocity 1.5 L/T
    assert plan.arrival_s == pytest.approx([0.0, first, 9.0], rel=1e-12)


# ---- errors name the file and the line ----

def test_an_unreachable_row_is_named():
    err = error_of("x_in,y_in,z_in\n10,0,20\n# comment\n12,0,16\n0,0,31\n10,0,20\n")
    assert err.line == 5
    assert str(err).startswith("pts.csv line 5: waypoint (0, 0, 31) in is out of reach")


def test_a_row_outside_the_safety_envelope_is_named():
    err = error_of("x_in,y_in,z_in\n10,0,20\n20,0,10\n")  # DH zero: the forearm is level (th3 = 0)
    assert err.line == 3
    assert ("outside the crs arm's safety envelope: th3 DH = 0.00 deg is outside [8.59, 131.78] deg"
            in str(err))


def test_elbow_down_puts_the_crs_arm_outside_its_envelope():
    err = error_of("x_in,y_in,z_in\n10,0,20\n12,0,16\n", elbow="down")
    assert err.line == 2 and "with the elbow down" in str(err) and "th3 DH = -" in str(err)


def test_a_move_that_dips_out_of_the_envelope_between_two_good_rows_is_named():
    a, b = [9.4, -2, 4.8], [18.7, -1, 4.3]
    qa, qb = crs.ik([a, b])
    assert not crs_outside_envelope(np.stack([qa, qb])).any()  # both ends are inside
    # a synchronized move is a straight line in joint space; z dips below 4 in on it
    s = np.linspace(0, 1, 1001)[:, None]
    assert crs.fk(qa + s * (qb - qa))[:, 2].min() < 4.0
    err = error_of(f"x_in,y_in,z_in\n10,0,20\n{a[0]},{a[1]},{a[2]}\n{b[0]},{b[1]},{b[2]}\n")
    assert err.line == 4
    assert "the move from line 3 to this row leaves the crs arm's safety envelope" in str(err)
    assert "in is below 4 in" in str(err)


def test_a_time_too_short_for_the_speed_limit_is_named():
    err = error_of("x_in,y_in,z_in,t_s\n10,0,20,0\n12,0,16,2\n10,0,20,2.1\n", profile="quintic")
    assert err.line == 4
    assert "reaching this row from line 3: 0.1 s is too fast for the quintic profile" in str(err)


@pytest.mark.parametrize("text, line, words", [
    ("x_in,y_in,z_in,t_s\n10,0,20,0\n12,0,16,3\n10,0,20,3\n", 4, "does not come after the 3 s of line 3"),
    ("x_in,y_in,z_in,t_s\n10,0,20,1\n12,0,16,3\n", 2, "the first row's t_s must be 0"),
    ("x_in,y_in,z_in,t_s\n10,0,20,\n14,-6,12,\n10,0,20,0.5\n", 4, "but the arm only gets to line 3 at"),
    ("x_in,y_in,z_in,speed_in_s\n10,0,20,\n12,0,16,-1\n", 3, "speed -1 in/s must be positive"),
    ("x_in,y_in,z_in\n10,0,20\n12,zero,16\n", 3, "y_in = 'zero' is not a number"),
    ("x_in,y_in,z_in\n10,0,20\n12,0\n", 3, "2 values for the 3 columns"),
    ("x_m,y_m,z_m\n1,0,2\n", 1, "the header must name the columns x_in, y_in, z_in (positions in in)"),
    ("x_in,y_in,z_in,t_s,speed_in_s\n1,0,2,0,\n", 1, "give t_s or speed_in_s, not both"),
    ("x_in,y_in,z_in\n10,0,nan\n12,0,16\n", 2, "z_in = 'nan' is not a number"),
])
def test_file_problems_name_the_line(text, line, words):
    err = error_of(text)
    assert err.line == line
    assert str(err).startswith(f"pts.csv line {line}: ")
    assert words in str(err)


def test_whole_file_problems_name_the_file(tmp_path):
    with pytest.raises(WaypointError, match=r"missing.csv: no such file"):
        read_waypoints(tmp_path / "missing.csv", name="missing.csv")
    with pytest.raises(WaypointError, match=r"pts.csv: needs at least two waypoints, found 1"):
        plan_text("x_in,y_in,z_in\n10,0,20\n")
    with pytest.raises(WaypointError, match=r"pts.csv: empty"):
        plan_text("# nothing here\n\n")


def test_a_file_on_disk_reads_like_a_stream(tmp_path):
    path = tmp_path / "pts.csv"
    path.write_text("x_in,y_in,z_in,t_s\n10,0,20,0\n12,0,16,2\n")
    pts = read_waypoints(path)
    assert pts.name == str(path) and pts.xyz.tolist() == [[10, 0, 20], [12, 0, 16]]
    assert pts.t_s.tolist() == [0.0, 2.0]


# ---- the envelope's reasons agree with the C core's test ----

def test_the_reason_given_agrees_with_the_envelope_test():
    rng = np.random.default_rng(8)
    q = rng.uniform([-2.5, -1.0, -0.5], [2.5, 2.0, 2.5], size=(3000, 3))
    outside = crs_outside_envelope(q)
    assert 0.2 < outside.mean() < 0.9  # the sample straddles the boundary
    reasons = [crs_why_outside(row) for row in q]
    assert [r != "inside the envelope" for r in reasons] == outside.tolist()
    below = crs.dh_to_motor([0.0, 0.1, 1.0])  # angles in range, the hand below 4 in
    assert crs_why_outside(below) == f"z = {crs.fk(below)[2]:.4g} in is below 4 in"


# ---- the spatial RRR arm of seed 003 ----

def plan_rrr(text, **kw):
    return plan_waypoints(read_waypoints(io.StringIO(text), length_unit="units", name="rrr.csv"), "rrr", **kw)


def test_rrr_rows_are_reached_with_the_elbow_above_the_line_to_the_target():
    from crslab.robots import load

    rrr = load("rrr")
    # seed 003's check point first, then points in other quadrants, one straight below the
    # first link's end
    pts = [[17.85, 2.698, 5.219], [12, 0, -3], [8, 6, -6], [-9, -9, -4]]
    text = "x_units,y_units,z_units\n" + "\n".join(",".join(map(str, p)) for p in pts) + "\n"
    plan = plan_rrr(text, profile="quintic", vmax_rad_s=2.0)
    q = plan.trajectory.evaluate(plan.arrival_s).q
    np.testing.assert_allclose(rrr.fk(q)[:, :3, 3], pts, atol=1e-9)
    # elbow up: in the arm's plane the elbow (a2 cos q2, a2 sin q2) lies counter-clockwise of (above)
    # the direction from the shoulder to the target
    a2 = rrr.chain.a[1]
    target_u = np.hypot(np.array(pts)[:, 0], np.array(pts)[:, 1]) - rrr.chain.a[0]
    target_w = np.array(pts)[:, 2] - rrr.chain.d[0]
    cross = target_u * a2 * np.sin(q[:, 1]) - target_w * a2 * np.cos(q[:, 1])
    assert np.all(cross > 0)
    down = plan_rrr("x_units,y_units,z_units\n17.85,2.698,5.219\n15,0,4\n", elbow="down")
    assert down.q_rad[0].round(2).tolist() == [0.15, 0.29, 0.57]  # seed 003's own solution


def test_rrr_rows_out_of_reach_or_outside_the_joint_limits_are_named():
    err = pytest.raises(WaypointError, plan_rrr, "x_units,y_units,z_units\n17.85,2.698,5.219\n30,0,0\n")
    assert str(err.value).startswith("rrr.csv line 3: waypoint (30, 0, 0) units is out of reach")
    # elbow down to a point below the first link: the shoulder would have to turn to -125 deg
    err = pytest.raises(WaypointError, plan_rrr, "x_units,y_units,z_units\n17.85,2.698,5.219\n12,0,-3\n",
                        elbow="down")
    assert err.value.line == 3
    assert ("outside the rrr arm's joint limits: joint 2 = -125.2 deg is outside [-90, 90] deg"
            in str(err.value))
