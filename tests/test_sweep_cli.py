"""`crslab sweep` as a student runs it: bad input is one line, crashes and hangs are rows, the
metrics are those of the run's signals, a golden file is compared, Ctrl-C keeps the finished rows."""

import csv
import signal
import subprocess
import sys
from pathlib import Path

import matplotlib.image
import numpy as np
import pytest

from crslab.cli import main
from crslab.framework_facts import CLAMP_UNITS
from crslab.run.api import simulate
from crslab.sweep.run_metrics import METRIC_NAMES
from crslab.sweep.table import shown_metrics
from tests.waiting import LineWatcher, wait_exit

NULL_AT = ("crash_after_5s.c used a NULL pointer (its address was 0) at crash_after_5s.c:27 in "
           "lab() at tick 5100")

LABS = Path(__file__).parent / "labs"
PD = LABS / "sweep_pd.c"
FAST = ["--scenario", "hands_off", "--duration", "1", "--no-startup-delay"]


def sweep(*args):
    return main(["sweep", *map(str, args)])


def rows_of(path):
    with path.open() as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize(
    "args, message",
    [
        (
            ["--vary", "frictoin=0:1"],
            "--vary frictoin: unknown name; valid: friction, friction1, friction2, friction3, "
            "payload_kg, mass, rest_offset2, rest_offset3, encoder_noise_counts, motor_gain, "
            "var:Kp2, var:Kd2, var:target2, var:tau1_open, var:steps, var:gains[i]",
        ),
        (
            ["--vary", "var:Kq=0:1"],
            "--vary var:Kq: Kq is not a watched (#pragma DATA_SECTION) variable of sweep_pd.c "
            "(watched: Kp2, Kd2, target2, tau1_open, steps, gains)",
        ),
        (["--vary", "friction=1"], "--vary friction=1: expected NAME=LO:HI (e.g. friction=0.5:1.5)"),
        (
            ["--vary", "var:steps=0:1e10"],
            "--vary var:steps: 1e+10 does not fit steps, int in sweep_pd.c (-32768 to 32767)",
        ),
    ],
)
def test_a_bad_vary_is_one_line_and_exit_2(tmp_path, capsys, args, message):
    assert sweep("--lab", PD, *FAST, *args, "--samples", "2", "-o", tmp_path / "r.csv") == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"crslab sweep: {message}"), err
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_other_bad_input(tmp_path, capsys):
    base = ["--lab", PD, *FAST, "--vary", "friction=0:1"]
    assert sweep(*base, "--samples", "2", "-o", tmp_path / "r.xlsx") == 2
    assert sweep(*base, "--samples", "0", "-o", tmp_path / "r.csv") == 2
    assert (
        sweep(
            "--lab",
            LABS / "does_not_compile.c",
            *FAST,
            "--vary",
            "friction=0:1",
            "--samples",
            "1",
            "-o",
            tmp_path / "r.csv",
        )
        == 2
    )
    assert sweep(*base, "--samples", "1", "--dask", "local:2", "--jobs", "2", "-o", tmp_path / "r.csv") == 2
    err = capsys.readouterr().err.splitlines()
    assert err[0].endswith("r.xlsx: the table must be a .csv or a .parquet file")
    assert err[1].endswith("--samples must be within 1 .. 1000000, got 0")
    assert err[-2] == "crslab sweep: does_not_compile.c does not compile"
    assert err[-1].startswith("crslab sweep: --jobs is for this machine's processes")
    assert not any(tmp_path.iterdir())


def test_crashes_and_hangs_are_rows_and_the_sweep_finishes(tmp_path, capsys):
    out = tmp_path / "crash.csv"
    assert (
        sweep(
            "--lab",
            LABS / "crash_after_5s.c",
            "--scenario",
            "hands_off",
            "--duration",
            "6",
            "--vary",
            "friction=0.5:1.5",
            "--samples",
            "2",
            "-o",
            out,
        )
        == 1
    )
    rows = rows_of(out)
    assert [(r["sample"], r["status"], r["passed"]) for r in rows] == [
        ("0", "crashed", "False"),
        ("1", "crashed", "False"),
    ]
    assert rows[0]["message"].startswith(NULL_AT + "")
    assert rows[0]["end_s"] == "5.1"
    out = tmp_path / "hang.csv"
    assert (
        sweep(
            "--lab",
            LABS / "hang_after_5s.c",
            "--scenario",
            "hands_off",
            "--duration",
            "6",
            "--deadline",
            "0.5",
            "--vary",
            "mass=1:1",
            "--grid",
            "1",
            "-o",
            out,
            "--plot",
            tmp_path / "p.png",
        )
        == 1
    )
    [row] = rows_of(out)
    assert row["status"] == "hung" and "lab() did not return within 0.5 s at tick 5100" in row["message"]
    # the hung run keeps the metrics of the 5.1 s it ran (docs/sweep.md): still, with no torque, its
    # motor angles as the encoders read them at its last tick, nothing else
    assert shown_metrics([row]) == ["theta2motor_final_rad", "theta3motor_final_rad"]
    assert float(row["end_s"]) == 5.1 and float(row["safety_trips"]) == 0
    # the plot: none of the metrics it shows unless asked, so one panel (its end time against the
    # mass, 4.0 by 3.1 in at 100 dpi) whose one point, a failed run's red x, sits in the middle (a
    # lone point is centred); the legend's red x is elsewhere
    image = matplotlib.image.imread(tmp_path / "p.png")
    assert image.shape[:2] == (310, 400)
    red = (image[..., 0] > 0.7) & (image[..., 1] < 0.35) & (image[..., 2] < 0.35)  # tab:red
    assert red[120:200, 160:260].sum() > 10 and red.sum() < 3 * red[120:200, 160:260].sum()
    stdout = capsys.readouterr().out
    assert "status: hung 1" in stdout and "passed: 0 of 1 (0.0 %)" in stdout
    assert "worst: sample 0 (hung, failed) at mass=1; hang_after_5s.c hung" in stdout


def test_metrics_are_those_of_the_runs_signals(tmp_path, drawn_figures):
    """The row's metrics against the same run's scope log, computed here another way; the plot
    draws each of them against each varied quantity, passed and failed runs apart."""
    out = tmp_path / "r.csv"
    assert (
        sweep(
            "--lab",
            PD,
            *FAST,
            "--vary",
            "var:Kp2=60:60",
            "--vary",
            "var:tau1_open=0:1",
            "--grid",
            "2",
            "-o",
            out,
            "--plot",
            tmp_path / "p.png",
        )
        == 1
    )
    rows = rows_of(out)
    [fig] = drawn_figures
    # without --plot-metrics: up to four of the usual ones, of those whose value differs between runs
    varying = [m for m in METRIC_NAMES if len({r[m] for r in rows}) > 1]
    metrics = [m for m in ("safety_trips", "motor_board_cutouts", "plotvar1_err_rms", "plotvar2_err_rms",
                           "plotvar3_err_rms", "clamp_share") if m in varying][:4]
    assert "plotvar2_err_rms" in metrics and len(fig.axes) == 2 * len(metrics)
    for i, metric in enumerate(metrics):
        for j, varied in enumerate(("var:Kp2", "var:tau1_open")):
            ax = fig.axes[2 * i + j]
            passed, failed = (c.get_offsets() for c in ax.collections)
            for drawn, want in ((passed, "True"), (failed, "False")):
                np.testing.assert_allclose(drawn, [(float(r[varied]), float(r[metric])) for r in rows
                                                   if r["passed"] == want])
        assert fig.axes[2 * i].get_ylabel() == metric
    from crslab.scenario.load import parse_scenario

    for row in rows:
        text = (
            'end = 1.0\n[[event]]\nat = 0\nkind = "set"\nvar = "Kp2"\nvalue = 60\n'
            f'[[event]]\nat = 0\nkind = "set"\nvar = "tau1_open"\nvalue = {row["var:tau1_open"]}\n'
        )
        run = simulate(PD, parse_scenario(text, Path("s.toml")), startup_delay=False, log=True)
        log = run.log
        plot = [[float(x) for x in r] for r in log["plot"]]
        err2 = [r[1] - r[3] for r in plot]
        assert float(row["plotvar2_err_rms"]) == pytest.approx(
            (sum(e * e for e in err2) / len(err2)) ** 0.5, rel=1e-12
        )
        assert float(row["plotvar4_maxabs"]) == pytest.approx(max(abs(r[3]) for r in plot))
        clamped = sum(1 for r in log["tau_lab"] if max(abs(float(x)) for x in r) >= CLAMP_UNITS)
        assert float(row["clamp_share"]) == pytest.approx(clamped / len(plot)) and clamped > 0
        safety = [int(s) for s in log["safety"].ravel()]
        trips = sum(1 for a, b in zip([0, *safety], safety) if b and not a)
        assert int(row["safety_trips"]) == trips
        assert float(row["theta1motor_final_rad"]) == float(log["enc_rad"][-1][0])
    # an open-loop torque on joint 1 drives the arm out of the envelope: that sample fails
    assert [(r["var:tau1_open"], r["safety_trips"], r["passed"]) for r in rows] == [
        ("0.0", "0", "True"),
        ("1.0", "1", "False"),
    ]


def test_motor_board_cutouts_are_counted(tmp_path):
    out = tmp_path / "r.csv"
    assert (
        sweep(
            "--lab",
            LABS / "saturating_gen_b.c",
            *FAST[:2],
            "--duration",
            "3",
            "--no-startup-delay",
            "--vary",
            "friction=1:1",
            "--grid",
            "1",
            "-o",
            out,
        )
        == 1
    )
    [row] = rows_of(out)
    run = simulate(LABS / "saturating_gen_b.c", "hands_off", duration_s=3.0, startup_delay=False)
    cutouts = sum(1 for _, _, off in run.stats.motor_board_events if off)
    assert int(row["motor_board_cutouts"]) == cutouts >= 1 and row["passed"] == "False"


def test_a_golden_file_is_compared_and_gives_the_defaults(tmp_path, capsys):
    golden = tmp_path / "g.txt"
    assert main(["record", "--lab", str(PD), *FAST, "-o", str(golden)]) == 0
    out = tmp_path / "r.csv"
    # no --scenario, --duration or --no-startup-delay: the golden file's
    assert (
        sweep("--lab", PD, "--golden", golden, "--vary", "var:target2=0.1:0.4", "--grid", "2", "-o", out) == 1
    )
    rows = rows_of(out)
    assert [(r["var:target2"], r["golden_match"], r["passed"]) for r in rows] == [
        ("0.1", "True", "True"),
        ("0.4", "False", "False"),
    ]
    assert rows[0]["end_s"] == "1.0"
    assert "transcript differs from the golden file: 1" in capsys.readouterr().out


def test_ctrl_c_keeps_the_finished_rows(tmp_path):
    out = tmp_path / "r.csv"
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "crslab",
            "sweep",
            "--lab",
            str(PD),
            "--scenario",
            "hands_off",
            "--duration",
            "20",
            "--vary",
            "friction=0.5:1.5",
            "--samples",
            "40",
            "--jobs",
            "1",
            "-o",
            str(out),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    err = LineWatcher(proc.stderr, "crslab sweep's stderr")
    err.wait_for(r"^\[2/40\] sample 1: ok")
    proc.send_signal(signal.SIGINT)
    status = wait_exit(proc, "Ctrl-C")
    text = err.all()
    assert status == 130, text
    proc.stdout.close()
    rows = rows_of(out)
    assert 2 <= len(rows) < 40 and [int(r["sample"]) for r in rows] == list(range(len(rows)))
    assert f"interrupted after {len(rows)} of 40 runs" in text and "Traceback" not in text
    assert not (tmp_path / "r.csv.partial.csv").exists()
    assert np.all([r["status"] == "ok" for r in rows])


def test_plot_metrics_draws_a_panel_per_varied_quantity_for_each_metric_asked(tmp_path, drawn_figures,
                                                                              capsys):
    """--plot-metrics: the metrics asked, one panel per varied quantity each; one every run has the
    same value of is left out, and said so; a misspelt one is one line with the right name."""
    out = tmp_path / "r.csv"
    asked = "plotvar2_err_rms,motor_board_cutouts,safety_trips"
    sweep("--lab", PD, *FAST, "--vary", "var:Kp2=40:80", "--vary", "var:tau1_open=0:1", "--grid", "2",
          "-o", out, "--plot", tmp_path / "p.png", "--plot-metrics", asked)
    rows = rows_of(out)
    assert {r["motor_board_cutouts"] for r in rows} == {"0"}  # Gen B's board never cut out here
    [fig] = drawn_figures
    assert [ax.get_ylabel() for ax in fig.axes[::2]] == ["plotvar2_err_rms", "safety_trips"]
    assert [ax.get_xlabel() for ax in fig.axes[-2:]] == ["var:Kp2", "var:tau1_open"]
    err = capsys.readouterr().err
    assert "--plot leaves out motor_board_cutouts: every run has the same value (0)" in err
    assert sweep("--lab", PD, *FAST, "--vary", "var:Kp2=40:80", "--grid", "2", "-o", out, "--plot",
                 tmp_path / "p.png", "--plot-metrics", "plotvar2_err_rm") == 2
    assert "no metric 'plotvar2_err_rm' (did you mean plotvar2_err_rms?)" in capsys.readouterr().err


def test_the_plots_tick_labels_do_not_overlap_and_a_whole_number_metric_has_whole_ticks():
    """Three quantities with long values side by side, a trip count of 0..3: no two tick labels of a
    panel overlap (their drawn boxes), and the count's ticks are whole numbers."""
    from crslab.sweep.table import figure
    from crslab.sweep.variations import parse_vary

    varies = [parse_vary("friction=0.51234:1.48766"), parse_vary("payload_kg=0.000125:0.000875"),
              parse_vary("rest_offset2=-0.02213:-0.01487"), parse_vary("mass=0.9:1.1")]
    rng = np.random.default_rng(3)
    rows = [{"passed": k % 2 == 0, "safety_trips": int(k % 4), "plotvar2_err_rms": float(rng.random()),
             **{v.name: v.low + (v.high - v.low) * rng.random() for v in varies}} for k in range(40)]
    fig = figure(rows, varies, title="t", metrics=["safety_trips", "plotvar2_err_rms"])
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        for labels in (ax.get_xticklabels(), ax.get_yticklabels()):
            boxes = [t.get_window_extent(renderer) for t in labels if t.get_text() and t.get_visible()]
            assert len(boxes) >= 2
            assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:]), ax.get_xlabel()
    for ax in fig.axes[:4]:  # the trips row
        lo, hi = ax.get_ylim()
        shown = [t for t in ax.get_yticks() if lo <= t <= hi]
        assert shown and all(float(t).is_integer() for t in shown), shown


def test_a_sweep_of_the_default_lab_that_passes_nothing_says_why(tmp_path, capsys):
    out = tmp_path / "r.csv"
    status = sweep("--vary", "friction=0.9:1.1", "--grid", "2", "-o", out)  # the whole tour
    printed = capsys.readouterr().out
    assert status == 1 and "passed: 0 of 2 (0.0 %); left the safety envelope: 2" in printed, printed
    assert ("note: nothing passed: crslab's own Lab 1 (the lab without --lab) applies no torque, so on the "
            "tour, where a hand moves the arm about and lets go, it stays in the safety envelope only where "
            "friction holds it; that is the lab, not your setup: sweep your own lab with --lab "
            "FILE\n") in printed
