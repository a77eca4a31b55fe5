"""--csv writes the scope signals one row per tick with units; `crslab plot` draws them, a panel per group."""

import csv

import matplotlib.image
import numpy as np
import pytest

from crslab.cli import main
from crslab.run.api import simulate
from crslab.scopes.plot import read_scope_csv, scope_figure
from crslab.scopes.signals import GROUPS, PUSH, SIGNALS
from crslab.sinks.csv_file import CsvSink


@pytest.fixture(scope="module")
def csv_run(tmp_path_factory):
    path = tmp_path_factory.mktemp("csv") / "run.csv"
    sink = CsvSink(path)
    run = simulate(duration_s=6.0, log=True, sinks=[sink])
    sink.close()
    return path, run


def test_one_row_per_tick_with_units_in_the_header(csv_run):
    path, run = csv_run
    with path.open() as f:
        rows = list(csv.reader(f))
    header = rows[0]
    assert header[:5] == ["tick", "t [s]", "theta1motor [rad]", "theta2motor [rad]", "theta3motor [rad]"]
    assert "tau1 [command units]" in header and "tau3_applied [command units]" in header
    assert "Simulink_PlotVar4 [lab units]" in header and "GPIO60 [0/1]" in header and "th2_dh [rad]" in header
    assert all(h.endswith("]") for h in header[1:])
    body = np.array(rows[1:], dtype=float)
    assert body[:, 0].tolist() == list(range(6000)) and np.allclose(body[:, 1], body[:, 0] / 1000)
    log = run.log
    col = {h: i for i, h in enumerate(header)}
    # the lab's C floats read back as the same floats, the plant's doubles as the same doubles
    f32 = np.float32
    np.testing.assert_array_equal(body[:, col["theta2motor [rad]"]].astype(f32),
                                  log["enc_rad"][:, 1].astype(f32))
    np.testing.assert_array_equal(body[:, col["Simulink_PlotVar4 [lab units]"]].astype(f32),
                                  log["plot"][:, 3].astype(f32))
    np.testing.assert_array_equal(body[:, col["th3_dh [rad]"]], log["qpos_dh_rad"][:, 2])
    np.testing.assert_array_equal(body[:, col["GPIO34 [0/1]"]], log["leds"][:, 0] & 1)


def coloured_pixels(image: np.ndarray) -> np.ndarray:
    """Where the image is coloured (a drawn line), not white, grey or black (frame, grid, text)."""
    rgb = image[..., :3]
    return rgb.max(axis=-1) - rgb.min(axis=-1) > 0.25


def test_plot_writes_a_png_with_one_labelled_panel_per_group(csv_run, tmp_path, capsys):
    path, _ = csv_run
    out = tmp_path / "fig.png"
    assert main(["plot", str(path), "-o", str(out), "--from", "3"]) == 0
    assert "6 panels (motor angles, torques, Simulink_PlotVar1..4" in capsys.readouterr().err
    image = matplotlib.image.imread(out)
    # six panels: 10 in by (2.2 * 6 + 0.8) in at 110 dpi
    assert image.shape[:2] == (round((2.2 * 6 + 0.8) * 110), 1100)
    t, values = read_scope_csv(path)
    keep = t >= 3
    fig = scope_figure(t[keep], {s: v[keep] for s, v in values.items()}, path.name)
    titles = [ax.get_title(loc="left") for ax in fig.axes]
    drawn = [g for g in GROUPS if g is not PUSH]  # the tour has no push: its panel is left out
    assert titles == [g.title for g in drawn]
    units = [ax.get_ylabel() for ax in fig.axes]
    assert units == ["rad", "command units", "lab units", "0/1 (a lane each)", "rad", "m"]
    assert [len(ax.get_lines()) for ax in fig.axes] == [sum(s.group == g for s in SIGNALS) for g in drawn]
    assert fig.axes[-1].get_xlabel() == "time (s)"
    # with a push the push's panel is drawn too
    pushed = {s: (np.full(len(v), 5.0) if s.group is PUSH else v) for s, v in values.items()}
    assert [ax.get_title(loc="left") for ax in scope_figure(t, pushed, "x").axes] == [g.title for g in GROUPS]
    # the data drawn is the CSV's, from 3 s on: each signal's line (the logic lanes offset)
    for ax, group in zip(fig.axes, drawn):
        members = [(s, v[keep]) for s, v in values.items() if s.group == group]
        for lane, (line, (s, v)) in enumerate(zip(ax.get_lines(), members)):
            assert line.get_label() == s.name
            np.testing.assert_array_equal(line.get_xdata(), t[keep])
            want = 0.8 * v + 1.2 * lane if group.unit == "0/1" else v
            np.testing.assert_array_equal(line.get_ydata(), want)
    # every panel of the PNG has its lines drawn in it: coloured pixels inside each axes box
    fig.set_dpi(110)
    fig.canvas.draw()
    height = image.shape[0]
    coloured = coloured_pixels(image)
    for ax in fig.axes:
        box = ax.get_window_extent()
        rows = slice(int(height - box.y1) + 2, int(height - box.y0) - 2)
        cols = slice(int(box.x0) + 2, int(box.x1) - 2)
        share = coloured[rows, cols].mean()
        assert share > 0.001, f"panel {ax.get_title(loc='left')!r} looks blank ({share:.4f} coloured)"
    assert not coloured[: int(height - fig.axes[0].get_window_extent().y1) - 2].any()  # none above


def test_plot_only_draws_the_groups_a_csv_holds(tmp_path):
    path = tmp_path / "cut.csv"
    path.write_text("tick,t [s],tau1 [command units],safety [0/1]\n0,0,1.5,0\n1,0.001,2,1\n")
    t, values = read_scope_csv(path)
    fig = scope_figure(t, values, "cut")
    assert [ax.get_title(loc="left") for ax in fig.axes] == ["torques", "safety flag, LEDs, motor board"]


def test_plot_bad_input_is_one_line_and_status_2(tmp_path, capsys):
    other = tmp_path / "other.csv"
    other.write_text("a,b\n1,2\n")
    empty = tmp_path / "empty.csv"
    empty.write_text("tick,t [s],tau1 [command units]\n")
    good = tmp_path / "good.csv"
    good.write_text("tick,t [s],tau1 [command units]\n0,0,1\n")
    for args, why in [([str(tmp_path / "none.csv")], "no such file"),
                      ([str(other)], "not a crslab scope CSV"), ([str(empty)], "holds no rows"),
                      ([str(good), "--from", "5"], "no rows between"),
                      ([str(good), "-o", str(good / "f.png")], "cannot write the figure")]:
        assert main(["plot", *args]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and why in err, err


def test_unwritable_scope_files_are_one_line_and_status_2(tmp_path, capsys):
    a_file = tmp_path / "a_file"
    a_file.write_text("not a folder")
    for option, path, why in [("--csv", a_file / "run.csv", "cannot write the CSV"),
                              ("--rrd", a_file / "run.rrd", "cannot write the rerun recording"),
                              ("--csv", tmp_path, "is a directory")]:
        assert main(["sim", "--fast", "--duration", "1", option, str(path)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and why in err, err
