"""Robot files (crslab.robots): every built-in loads, the CRS file is the C core's arm, user
files work, and a malformed file gets one clear error naming the file and the key."""

import numpy as np
import pytest

from crslab import crs, robots
from crslab.robots import RobotFileError

GOOD = """
name = "two_link"
source = "a test"
convention = "standard"
length_unit = "m"
[parameters]
l1 = 0.5
[[dh]]
a = "l1"
alpha = 0
d = 0
lower = "-90*deg"
upper = "pi/2"
[[dh]]
a = 0.25
alpha = 0
d = 0
"""


def write(tmp_path, text, name="arm.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("name", robots.names())
def test_every_built_in_robot_loads_with_its_source(name):
    robot = robots.load(name)
    assert robot.name == name and robot.source.strip() and robot.n_joints >= 3


def test_built_ins_are_the_six_course_robots():
    assert robots.names() == ["arm7r", "crs", "panda", "panda_mdh", "planar3r", "rrr"]


def test_crs_file_is_the_c_core_arm():
    """One truth: the CRS file's numbers are crslab.crs's (and the loader refuses others)."""
    c = robots.load("crs").chain
    assert c.d[0] == crs.BASE_HEIGHT_IN and c.a[1] == crs.UPPER_ARM_IN and c.a[2] == crs.FOREARM_IN
    assert c.alpha_rad[0] == -np.pi / 2


def test_crs_closed_form_refuses_other_dimensions(tmp_path):
    elbow = 'alpha = 0\nd = 0\n\n[[dh]]\nname = "elbow"'
    text = robots.robot_path("crs").read_text().replace(f"a = 10\n{elbow}", f"a = 11\n{elbow}")
    assert "a = 11" in text
    with pytest.raises(RobotFileError, match=r"crs\.toml: dh: closed_form 'crs' needs .*crslab\.crs"):
        robots.load(write(tmp_path, text, "crs.toml"))


def test_seed_003_limits_and_seed_002_centres_are_in_the_files():
    rrr = robots.load("rrr").chain
    np.testing.assert_allclose(rrr.lower, [-np.pi, -np.pi / 2, -np.pi])
    np.testing.assert_allclose(rrr.upper, [np.pi, np.pi / 2, np.pi])
    panda = robots.load("panda")
    assert panda.chain.joint_types[0] == "fixed" and panda.centres.shape == (8, 3)
    np.testing.assert_allclose(panda.centres[:, 2], [0, 0, 0.195, 0, 0.125, -0.015, 0.051, 0])


def test_a_user_file_by_path_with_expressions_and_parameters(tmp_path):
    path = write(tmp_path, GOOD)
    robot = robots.load(str(path))
    np.testing.assert_allclose(robot.chain.a, [0.5, 0.25])
    np.testing.assert_allclose(robot.chain.lower, [-np.pi / 2, -np.inf])
    np.testing.assert_allclose(robot.fk([np.pi / 2, 0])[:3, 3], [0, 0.75, 0], atol=1e-15)
    assert robots.load(path, {"l1": 1.0}).chain.a[0] == 1.0
    with pytest.raises(RobotFileError, match="no parameter 'l2' .parameters: l1."):
        robots.load(path, {"l2": 1.0})


@pytest.mark.parametrize("change, message", [
    (('alpha = 0\nd = 0\nlower', 'alpah = 0\nd = 0\nlower'), r"dh\[1\]\.alpah: unknown key"),
    (('a = "l1"', 'a = "l2 * 2"'), r"dh\[1\]\.a: unknown name 'l2' in 'l2 \* 2' \(known: pi, deg, l1\)"),
    (('a = "l1"', 'a = "__import__(1)"'), r"dh\[1\]\.a: cannot evaluate"),
    (('a = "l1"', 'a = "1 +"'), r"dh\[1\]\.a: cannot read '1 \+'"),
    (('a = "l1"', 'a = true'), r"dh\[1\]\.a: must be a number"),
    (('convention = "standard"', 'convention = "craig"'), r"convention: 'craig' is not one of standard"),
    (('length_unit = "m"', 'length_unit = "furlong"'), r"length_unit: 'furlong' is not one of"),
    (('length_unit = "m"\n', ''), r"length_unit: missing"),
    (('upper = "pi/2"', 'upper = "-pi"'), r"dh\[1\]\.lower: lower limit -1\.5708 is above upper limit"),
    (('source = "a test"', 'source = "a test"\nclosed_form = "spatial_rrr"'),
     r"closed_form: closed_form 'spatial_rrr'"),
    (('[parameters]', 'colour = "red"\n[parameters]'), r"colour: unknown key"),
    (('l1 = 0.5', 'pi = 3'), r"parameters\.pi: must be an identifier other than pi and deg"),
    (('d = 0\nlower', 'd = 0\njoint = "prismatic"\nlower'), r"dh\[1\]\.joint: 'prismatic' is not one of"),
    (('d = 0\nlower', 'd = 0\ncentre = [0, 0]\nlower'), r"dh\[1\]\.centre: must be a list of 3 numbers"),
    (('d = 0\nlower', 'd = 0\ncentre = [0, 0, 1]\nlower'), r"dh\[2\]\.centre: give a centre for every"),
])
def test_malformed_files_name_file_and_key(tmp_path, change, message):
    old, new = change
    assert old in GOOD
    path = write(tmp_path, GOOD.replace(old, new, 1))
    with pytest.raises(RobotFileError, match=message) as info:
        robots.load(path)
    text = str(info.value)
    assert text.startswith(str(path)) and "\n" not in text


def test_not_toml_and_missing_files(tmp_path):
    with pytest.raises(RobotFileError, match="not valid TOML"):
        robots.load(write(tmp_path, "name = \n"))
    with pytest.raises(RobotFileError, match="no such robot file"):
        robots.load(tmp_path / "nothing.toml")
    with pytest.raises(RobotFileError, match="no robot named 'r2d2' .known: arm7r, crs"):
        robots.load("r2d2")
    with pytest.raises(RobotFileError, match=r"dh: needs one \[\[dh\]\] table per DH row"):
        robots.load(write(tmp_path, 'name = "x"\nsource = "y"\nconvention = "standard"\nlength_unit = "m"\n'))
