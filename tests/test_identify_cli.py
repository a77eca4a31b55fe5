"""``crslab identify`` as a user runs it: a plant file and a plot out of a recording, the residual
table, bad input as one line naming the file (exit 2); and the plant file in ``crslab sim``,
``record`` and ``check`` (``--plant``, the golden header)."""

import subprocess
import sys
from pathlib import Path

import matplotlib.image
import pytest
from test_identify_fit import LAB, simulink_recording

from crslab.plant.plant_params import PlantParams

CRSLAB = [sys.executable, "-m", "crslab"]
LABS = Path(__file__).parent / "labs"


def crslab(*args, cwd=None, timeout=300):
    return subprocess.run([*CRSLAB, *map(str, args)], capture_output=True, text=True, cwd=cwd,
                          timeout=timeout)


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    plant = PlantParams.defaults().with_values({"stall_nm1": 14.4})
    path = tmp_path_factory.mktemp("cli") / "arm.csv"
    return simulink_recording(path, plant, start_tick=4210, phase_ms=1.0, drift=0.0, seconds=4.0)


@pytest.fixture(scope="module")
def identified(recording, tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    r = crslab("identify", recording, "--fit", "stall_nm1", "--max-iterations", "8", "--jobs", "2",
               "-o", out / "arm.toml", cwd=out)
    return r, out


def test_identify_writes_a_plant_file_a_plot_and_the_residuals(identified):
    r, out = identified
    assert r.returncode == 0, r.stderr
    plant = PlantParams.load(out / "arm.toml")
    assert plant.value("stall_nm1") == pytest.approx(14.4, rel=0.03)
    assert plant.value("stall_nm2") == PlantParams.defaults().value("stall_nm2")
    text = (out / "arm.toml").read_text()
    assert "# Recordings (lab that produced each, uncertainty per sample):" in text
    assert "lab2_square_pid.c" in text
    # the plot: a row per joint, the angles and the residual side by side (12 by 3 x 2.6 in at 110
    # dpi), the fitted plant's red curve drawn in each of the six panels
    image = matplotlib.image.imread(out / "arm.png")
    assert image.shape[:2] == (round(3 * 2.6 * 110), 12 * 110)
    r_, g_, b_ = image[..., 0], image[..., 1], image[..., 2]
    red = (r_ > 0.7) & (g_ < 0.35) & (b_ < 0.35)  # tab:red
    height, width = red.shape
    for row in range(3):
        for col in range(2):
            cell = red[row * height // 3:(row + 1) * height // 3, col * width // 2:(col + 1) * width // 2]
            assert cell.sum() > 200, f"panel ({row}, {col}) has no fitted curve"
    assert "stall_nm1" in r.stdout and "RMS before" in r.stdout
    for joint in (1, 2, 3):
        assert f"joint {joint}" in r.stdout
    assert "crslab sim --plant" in r.stderr and "runs" in r.stderr


def test_sim_record_and_check_run_with_the_plant_file(identified, tmp_path):
    _, out = identified
    plant = out / "arm.toml"
    r = crslab("sim", "--fast", "--quiet", "--duration", "5", "--plant", plant, "--scenario", "hands_off",
               "--lab", LAB)
    assert r.returncode == 0, r.stderr
    golden = tmp_path / "golden.txt"
    r = crslab("record", "--lab", LAB, "--scenario", "hands_off", "--duration", "5", "--plant", plant,
               "-o", golden)
    assert r.returncode == 0, r.stderr
    header = golden.read_text().split("\n# ----\n")[0]
    assert f"# plant: {plant}" in header and "# plant_sha256: " in header
    assert crslab("check", "--lab", LAB, "--golden", golden).returncode == 0  # the golden's plant is used
    weak = tmp_path / "weak.toml"
    weak.write_text("[drive]\nstall_nm = [3.6, 3.6, 3.6]\n")
    r = crslab("check", "--lab", LAB, "--golden", golden, "--plant", weak)
    assert r.returncode == 1  # another arm prints other angles
    assert f"note: plant file {weak} differs from the one {golden} was recorded with" in r.stderr


def test_a_default_golden_says_so_and_a_bad_plant_file_is_one_line(tmp_path):
    golden = tmp_path / "golden.txt"
    r = crslab("record", "--scenario", "hands_off", "--duration", "4.2", "-o", golden)
    assert r.returncode == 0 and "# plant: default\n" in golden.read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text("[drive]\nstall_nm = 3\n")
    r = crslab("sim", "--fast", "--duration", "1", "--plant", bad)
    assert r.returncode == 2 and r.stderr.count("\n") == 1
    assert f"{bad}:2: drive.stall_nm: must be three numbers" in r.stderr  # FILE:LINE: KEY: problem


@pytest.mark.parametrize("make, args, words", [
    (None, ["missing.csv"], "missing.csv: no such recording"),
    ("nocols", [], "no PlotVar columns"),
    ("short", [], "shorter than a step response"),
    ("rec", ["--fit", "stall"], "cannot fit 'stall'"),
    ("rec", ["--map", "1,2"], "three PlotVar numbers"),
    ("rec", ["REC", "--lab", "a.c", "--lab", "b.c", "--lab", "c.c"],
     "--lab is given 3 times for 2 recordings"),
    ("rec", ["--lab", "DOES_NOT_COMPILE"], "does_not_compile.c"),
    ("rec", ["--plant", "missing.toml"], "missing.toml: no such plant file"),
])
def test_bad_input_is_one_line_naming_it_and_exit_2(tmp_path, recording, make, args, words):
    rec = tmp_path / "rec.csv"
    if make == "nocols":
        rec.write_text("t,x\n0,1\n0.005,2\n")
    elif make == "short":
        rows = "".join(f"{i * 0.005},{i},{i},{i}\n" for i in range(1, 60))
        rec.write_text("t,PlotVar1,PlotVar2,PlotVar3\n" + rows)
    elif make == "rec":
        rec.write_bytes(recording.read_bytes())
    args = [str(LABS / "does_not_compile.c") if a == "DOES_NOT_COMPILE" else str(rec) if a == "REC" else a
            for a in args]
    r = crslab("identify", *([rec] if make else []), *args, "-o", tmp_path / "out.toml", cwd=tmp_path)
    assert r.returncode == 2, r.stderr
    errors = [line for line in r.stderr.splitlines() if line.startswith("crslab identify:")]
    assert len(errors) == 1 and words in errors[0], r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "out.toml").exists()


def test_identify_fits_a_friction_table_alone(tmp_path):
    """A table (what crslab friction writes) from another arm: crslab identify finds that arm's
    lines, prints the table before and after, writes the plant file; no recording, no plot."""
    from crslab.identify.friction_table import predict

    other = PlantParams.defaults().with_values({"coulomb_pos3": 3.5, "viscous_neg2": 2.2})
    table = tmp_path / "other.toml"
    table.write_text(predict(other).to_toml("another arm"))
    r = crslab("identify", table, "--fit", "friction", "-o", tmp_path / "arm.toml", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    fitted = PlantParams.load(tmp_path / "arm.toml")
    assert fitted.value("coulomb_pos3") == pytest.approx(3.5, rel=0.005)
    assert fitted.value("viscous_neg2") == pytest.approx(2.2, rel=0.005)
    assert "friction table other.toml" in r.stdout and "RMS gap" in r.stdout
    assert "# Friction tables (relative uncertainty of each number):" in (tmp_path / "arm.toml").read_text()
    assert not (tmp_path / "arm.png").exists() and "cross-validation" not in r.stdout


@pytest.mark.parametrize("text, args, words", [
    ("[joint1]\nVpos = 0.2\n", [], "[joint1] must give Vpos, Vneg, Cpos, Cneg"),
    ("[joint1]\nVpos = 0.2\nVneg = 0.2\nCpos = -0.3\nCneg = -0.3\n", [], "friction opposes motion"),
    ("uncertainty = 0\n[joint1]\nVpos = 0.2\nVneg = 0.2\nCpos = 0.3\nCneg = -0.3\n", [], "uncertainty = 0"),
    ("[joint1]\nVpos = 0.2\nVneg = 0.2\nCpos = 0.3\nCneg = -0.3\n", ["--fit", "drive"],
     "a friction table tells only friction"),
    ("[joint1]\nVpos = 0.2\nVneg = 0.2\nCpos = 0.3\nCneg = -0.3\n", ["--lab", "x.c"], "are for recordings"),
])
def test_a_bad_friction_table_is_one_line_naming_it(tmp_path, text, args, words):
    table = tmp_path / "t.toml"
    table.write_text(text)
    r = crslab("identify", table, *args, "-o", tmp_path / "out.toml", cwd=tmp_path)
    assert r.returncode == 2, r.stderr
    errors = [line for line in r.stderr.splitlines() if line.startswith("crslab identify:")]
    assert len(errors) == 1 and words in errors[0], r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "out.toml").exists()


def test_a_table_alone_announces_only_what_it_fits_and_why_no_plot(tmp_path):
    """The default --fit names drive, friction, static and inertia; a friction table tells friction
    and static friction only: the announcement says so, and why no picture is drawn."""
    from crslab.identify.friction_table import predict

    table = tmp_path / "other.toml"
    other = PlantParams.defaults().with_values({"coulomb_pos3": 3.5})
    table.write_text(predict(other).to_toml("another arm"))
    r = crslab("identify", table, "-o", tmp_path / "new" / "arm.toml", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert ("crslab identify: fitting friction, static to 1 friction table (drive, inertia: not from "
            "friction tables alone, which tell only friction and the motor gain; give a "
            "recording)\n") in r.stderr
    assert ("crslab identify: no plot: it draws a recording against its simulated run, and only friction "
            "tables were given\n") in r.stderr
    assert (tmp_path / "new" / "arm.toml").is_file() and not (tmp_path / "new" / "arm.png").exists()


def test_the_help_says_the_default_uncertainty_as_a_number():
    from crslab.identify.fit import RECORDING_SIGMA_RAD

    r = crslab("identify", "--help")
    assert f"default: {RECORDING_SIGMA_RAD:g})" in " ".join(r.stdout.split()) and "{" not in r.stdout
