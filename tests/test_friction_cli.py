"""``crslab friction``: the course's Lab 3 friction identification on crslab's arm reproduces the
course's table (issue 23: every Coulomb and viscous value within 15 %, both directions, all
three joints), and a real arm's Tera Term log gives that arm's own table."""

import subprocess
import sys

import matplotlib.image
import numpy as np
import pytest

from crslab.identify.friction_table import KEYS, load_table, predict
from crslab.plant.plant_params import PlantParams
from crslab.resources import path as resource_path

CRSLAB = [sys.executable, "-m", "crslab"]
COURSE = resource_path("models", "crs_arm", "recordings", "lab3_friction_table_course.toml")


def crslab(*args, cwd=None):
    return subprocess.run([*CRSLAB, *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=300)


@pytest.fixture(scope="module")
def identified(tmp_path_factory):
    """The whole identification, as a student runs it: every joint, nine speeds each way."""
    out = tmp_path_factory.mktemp("friction")
    return crslab("friction", "-o", out / "table.toml", cwd=out), out


def test_lab3_identification_on_crslabs_arm_reproduces_the_course_table(identified):
    r, out = identified
    assert r.returncode == 0, r.stderr
    measured, course = load_table(out / "table.toml"), load_table(COURSE)
    for joint in (1, 2, 3):
        for key in KEYS:
            got, want = measured.value(joint, key), course.value(joint, key)
            assert abs(got / want - 1) <= 0.15, (joint, key, got, want)
    # what the lab measured is what crslab's friction law says the method finds (independently of
    # the run: the law's lines through the same speeds), to 1 % of each number
    expected = predict(PlantParams.defaults(), measured.speeds_rad_s)
    for (joint, key), value in expected.values().items():
        assert measured.value(joint, key) == pytest.approx(value, rel=0.01), (joint, key)
    # the printed table: the course's units, the course beside it, the gaps
    lines = r.stdout.splitlines()
    assert "Vpos" in lines[1] and "Cneg" in lines[1]
    row = next(line for line in lines if line.startswith("joint 2"))
    printed = [float(v) for v in row.split()[2:6]]
    assert printed == pytest.approx([measured.value(2, k) for k in KEYS], abs=6e-5)
    assert sum(line.strip().startswith("course") for line in lines) == 3
    assert sum(line.strip().startswith("gap") for line in lines) == 3


def test_the_plot_shows_each_joints_points_and_both_lines(identified):
    _, out = identified
    image = matplotlib.image.imread(out / "table.png")
    assert image.shape[:2] == (round(4.2 * 110), round(3 * 5.2 * 110))
    red = (image[..., 0] > 0.7) & (image[..., 1] < 0.35) & (image[..., 2] < 0.35)
    black = (image[..., 0] < 0.2) & (image[..., 1] < 0.2) & (image[..., 2] < 0.2)
    width = red.shape[1]
    for panel in range(3):
        cells = slice(panel * width // 3, (panel + 1) * width // 3)
        assert red[:, cells].sum() > 800, f"joint {panel + 1}: no points or lines of crslab's"
        assert black[:, cells].sum() > 500, f"joint {panel + 1}: no course lines"


def test_a_real_arms_tera_term_log_gives_its_own_table(tmp_path):
    """The lab's lines, as Tera Term saved them (with whatever else was printed), from an arm whose
    friction is u = 0.30 w + 0.40 positive and u = 0.20 w - 0.35 negative on joint 1."""
    log = tmp_path / "teraterm.log"
    speeds = (0.05, 0.1, 0.2, 0.5, 1.0, 2.0)
    lines = ["Lab 3 friction identification: joint, speed (rad/s), mean command (units)"]
    for w in speeds:
        lines.append(f"joint 1 speed {w:.4f} rad/s command {0.30 * w + 0.40:.4f}")
        lines.append(f"joint 1 speed {-w:.4f} rad/s command {0.20 * -w - 0.35:.4f}")
        lines.append("some other line 1.0 2.0")
    log.write_text("\n\r".join(lines) + "\n\rdone\n\r")
    r = crslab("friction", "--log", log, "--joints", "1", "-o", tmp_path / "mine.toml", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    mine = load_table(tmp_path / "mine.toml")
    assert [mine.value(1, k) for k in KEYS] == pytest.approx([0.30, 0.20, 0.40, -0.35], abs=1e-4)
    assert list(mine.rows) == [1]
    assert "running" not in r.stderr  # nothing was simulated
    gaps = next(line for line in r.stdout.splitlines() if line.strip().startswith("gap")).split()[1:]
    assert gaps[0] == f"{0.30 / 0.2513 - 1:+.1%}"
    assert (tmp_path / "mine.png").is_file()


def test_a_short_run_measures_only_what_it_is_asked(tmp_path):
    r = crslab("friction", "--joints", "3", "--speeds", "0.3,1.2", "-o", tmp_path / "t.toml", "--plot",
               tmp_path / "fig.png", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    table = load_table(tmp_path / "t.toml")
    assert list(table.rows) == [3] and table.speeds_rad_s == (0.3, 1.2)
    expected = predict(PlantParams.defaults(), (0.3, 1.2))
    assert table.value(3, "Vneg") == pytest.approx(expected.value(3, "Vneg"), rel=0.01)
    assert (tmp_path / "fig.png").is_file() and not (tmp_path / "t.png").exists()


@pytest.mark.parametrize("args, words", [
    (["--log", "missing.log"], "missing.log: cannot be read"),
    (["--log", "EMPTY"], "no 'joint N speed W rad/s command U' lines"),
    (["--log", "EMPTY", "--plant", "x.toml"], "--lab and --plant are for a run on crslab's arm"),
    (["--speeds", "0.5"], "give 2 to 9 motor speeds"),
    (["--speeds", "0.5,-1"], "give 2 to 9 motor speeds"),
    (["--joints", "4"], "joints are 1, 2 and 3"),
    (["--reference", "nowhere.toml"], "nowhere.toml: no such friction table"),
    (["--plant", "nowhere.toml"], "nowhere.toml: no such plant file"),
    (["--lab", "OTHER_LAB"], "lab2_square_pid.c does not watch n_speeds, speeds_rad_s, measure_joint"),
])
def test_bad_input_is_one_line_and_nothing_is_written(tmp_path, args, words):
    (tmp_path / "EMPTY").write_text("nothing here\n")
    other = resource_path("csrc", "labs", "lab2_square_pid.c")
    args = [str(other) if a == "OTHER_LAB" else a for a in args]
    r = crslab("friction", *args, "-o", tmp_path / "out.toml", cwd=tmp_path)
    assert r.returncode == 2, r.stderr
    errors = [line for line in r.stderr.splitlines()
              if "error" in line or line.startswith("crslab friction:")]
    assert any(words in line for line in errors), r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "out.toml").exists()


def test_the_table_file_round_trips(tmp_path):
    table = predict(PlantParams.defaults())
    path = tmp_path / "t.toml"
    path.write_text(table.to_toml("a test"))
    back = load_table(path)
    np.testing.assert_allclose(list(back.values().values()), list(table.values().values()), rtol=1e-5)
    assert back.speeds_rad_s == table.speeds_rad_s


def test_an_output_in_a_new_folder_is_made_and_one_that_cannot_be_is_said_before_the_run(tmp_path):
    log = tmp_path / "teraterm.log"
    log.write_text("".join(f"joint 1 speed {s * w:.4f} rad/s command {s * (0.3 * w + 0.4):.4f}\n"
                           for w in (0.1, 0.5, 1.0) for s in (1, -1)))
    r = crslab("friction", "--log", log, "--joints", "1", "-o", tmp_path / "fric" / "table.toml",
               "--plot", tmp_path / "fric2" / "p.png", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "fric" / "table.toml").is_file() and (tmp_path / "fric2" / "p.png").is_file()
    (tmp_path / "a_file").write_text("not a folder\n")
    for args, bad in ((["-o", tmp_path / "a_file" / "t.toml"],
                       "a_file/t.toml: cannot write the table there (a_file is a file, not a folder)"),
                      (["--plot", tmp_path / "a_file" / "p.png"],
                       "a_file/p.png: cannot write the plot there (a_file is a file, not a folder)")):
        r = crslab("friction", "--joints", "3", *args, cwd=tmp_path)  # crslab's arm: a long run
        assert r.returncode == 2 and "running" not in r.stderr, r.stderr
        assert r.stderr.strip().splitlines()[-1].endswith(bad), r.stderr
