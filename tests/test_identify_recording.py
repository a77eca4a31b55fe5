"""Reading recordings for ``crslab identify``: the course's Simulink exports (.mat in its layouts,
CSV), crslab's own --csv, which PlotVar is which, and bad files as one line naming them."""

import numpy as np
import pytest
from scipy.io import savemat

from crslab.identify import align
from crslab.identify.recording import PlotVarMap, RecordingError, read_recording

T = np.round(np.arange(0, 2.0, 0.005), 6)
PLOT = np.stack([np.sin(T), np.cos(T), T / 2, np.where(T < 1, 0.5236, 0.0)], axis=1)
PLOT[:2] = 0.0  # Simulink records zeros until the board answers


def check(rec, first=2):
    """``rec`` holds T and PLOT from the first answered sample on (to the 6 decimals the CSVs hold)."""
    np.testing.assert_allclose(rec.t_s, T[first:], atol=1e-6)
    np.testing.assert_allclose(rec.plotvars, PLOT[first:], atol=1e-6)
    np.testing.assert_allclose(rec.motor_rad, PLOT[first:, :3], atol=1e-6)
    assert rec.joints == (1, 2, 3)


def test_mat_array_with_time_in_the_first_column(tmp_path):
    path = tmp_path / "PID.mat"
    savemat(path, {"PID": np.column_stack([T, PLOT])})  # what Simulink's "Array" format saves
    check(read_recording(path))


def test_mat_structure_with_time_one_signal_of_four(tmp_path):
    path = tmp_path / "scope.mat"
    savemat(path, {"ScopeData": {"time": T, "signals": {"values": PLOT, "dimensions": 4, "label": ""}}})
    check(read_recording(path))


def test_mat_structure_with_time_one_signal_per_plotvar(tmp_path):
    path = tmp_path / "scope.mat"
    signals = np.array([{"values": PLOT[:, k:k + 1], "dimensions": 1} for k in range(4)], dtype=object)
    savemat(path, {"ScopeData": {"time": T, "signals": signals}})
    check(read_recording(path))


def test_mat_separate_plotvar_vectors_beside_tout(tmp_path):
    path = tmp_path / "vars.mat"
    savemat(path, {"tout": T, **{f"Simulink_PlotVar{k + 1}": PLOT[:, k] for k in range(4)}})
    check(read_recording(path))


def test_mat_separate_structures_with_time(tmp_path):
    path = tmp_path / "vars.mat"
    savemat(path, {f"PlotVar{k + 1}": {"time": T, "signals": {"values": PLOT[:, k]}} for k in range(4)})
    check(read_recording(path))


def test_csv_with_t_s_and_named_plotvars(tmp_path):
    path = tmp_path / "rec.csv"
    header = "t_s,PlotVar1_theta1motor_rad,PlotVar2_theta2motor_rad,PlotVar3_theta3motor_rad,PlotVar4_ref"
    np.savetxt(path, np.column_stack([T, PLOT]), delimiter=",", header=header, comments="", fmt="%.6f")
    check(read_recording(path))


def test_crslab_csv(tmp_path):
    """crslab sim --csv: a row per tick, the PlotVars among many columns (here every 5th tick kept)."""
    path = tmp_path / "run.csv"
    cols = ["tick", "t [s]", "theta1motor [rad]", *(f"Simulink_PlotVar{k} [lab units]" for k in (1, 2, 3, 4)),
            "safety [0/1]"]
    rows = np.column_stack([np.arange(len(T)), T, PLOT[:, 0], PLOT, np.zeros(len(T))])
    np.savetxt(path, rows, delimiter=",", header=",".join(cols), comments="", fmt="%.6f")
    check(read_recording(path))


def test_map_picks_the_plotvars_and_leaves_joints_out(tmp_path):
    path = tmp_path / "PID.mat"
    savemat(path, {"PID": np.column_stack([T, PLOT])})
    rec = read_recording(path, PlotVarMap.parse("3,-,1"))
    assert rec.joints == (1, 3)
    np.testing.assert_allclose(rec.motor_rad, PLOT[2:][:, [2, 0]])
    assert str(rec.map) == "3,-,1"


@pytest.mark.parametrize("text, words", [
    ("1,2", "three PlotVar numbers"), ("1,2,5", "'5' is not a PlotVar number"), ("-,-,-", "names no motor"),
    ("1,1,2", "uses a PlotVar twice"),
])
def test_bad_maps(text, words):
    with pytest.raises(ValueError, match=words):
        PlotVarMap.parse(text)


def test_a_window_keeps_the_samples_between(tmp_path):
    path = tmp_path / "PID.mat"
    savemat(path, {"PID": np.column_stack([T, PLOT])})
    rec = read_recording(path).window(0.5, 1.0)
    assert rec.t_s[0] - T[2] == pytest.approx(0.5) and rec.t_s[-1] - T[2] == pytest.approx(1.0)
    with pytest.raises(RecordingError, match="fewer than 3 samples"):
        read_recording(path).window(5.0, None)


def bad(tmp_path, name, content):
    path = tmp_path / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    elif isinstance(content, str):
        path.write_text(content)
    else:
        savemat(path, content)
    return path


@pytest.mark.parametrize("name, content, words", [
    ("rec.csv", "time,x\n0,1\n", "no PlotVar columns"),
    ("rec.csv", "PlotVar1,PlotVar2\n0,1\n", "no time column"),
    ("rec.csv", "t,PlotVar1,PlotVar2,PlotVar3\n0,1,2,3\n0.005,1,x,3\n", "not numbers"),
    ("rec.csv", "t,PlotVar1,PlotVar3\n0,1,3\n0.005,1,3\n0.01,1,3\n", "has no PlotVar2"),
    ("rec.csv", "t,PlotVar1,PlotVar2,PlotVar3\n0,1,2,3\n0,1,2,3\n0.01,1,2,3\n", "does not increase"),
    ("rec.csv", "t,PlotVar1,PlotVar2,PlotVar3\n0,0,0,0\n0.005,0,0,0\n0.01,1,2,3\n", "fewer than 3 samples"),
    ("rec.mat", b"not a mat file at all", "not a MATLAB .mat file"),
    ("rec.mat", {"a": np.ones((3, 5)), "b": np.ones((3, 5))}, "expected one Simulink recording"),
    ("rec.mat", {"a": np.ones((3, 1))}, "expected one Simulink recording"),
    ("rec.xlsx", "", "not a recording crslab reads"),
])
def test_bad_recordings_are_one_line_naming_the_file(tmp_path, name, content, words):
    path = bad(tmp_path, name, content)
    with pytest.raises(RecordingError) as exc:
        read_recording(path)
    message = str(exc.value)
    assert message.startswith(f"{path}: ") and words in message and "\n" not in message
    with pytest.raises(RecordingError, match="no such recording"):
        read_recording(tmp_path / "missing.csv")


# -- alignment -------------------------------------------------------------------------------------

def test_coarse_start_finds_where_a_recording_lies_on_a_run():
    ticks = np.arange(20_000)
    square = (ticks // 1000) % 2 * 0.5
    per_tick = np.stack([np.sin(ticks / 300.0), np.cos(ticks / 170.0), ticks * 0.0, square], 1)
    t = np.arange(0, 3.0, 0.005)
    offset = 7321
    recorded = per_tick[offset + np.round(t * 1000).astype(int)]
    assert align.coarse_start(per_tick, recorded, t, 3000, 12_000) == offset


def test_a_reference_pins_the_phase_and_the_drift():
    """A square wave toggling at tick 5000 + 1000 k, sampled every 5 ms from board time 4999.0 + 2.2
    on a clock 300 ppm slow: the toggles bound the phase to the sample period and the drift to what
    keeps every toggle inside its sample gap."""
    ticks = np.arange(30_000)
    square = ((ticks - 5000) // 1000 % 2 == 0).astype(float) * 0.5 * (ticks >= 5000)
    per_tick = np.stack([np.zeros_like(square), np.zeros_like(square), np.zeros_like(square), square], axis=1)
    t = np.arange(0, 10.0, 0.005)
    board = 4999.0 + 2.2 + t * 1000 * (1 - 300e-6)
    recorded = per_tick[np.floor(board).astype(int)]
    a = align.fine_bounds(per_tick, recorded, t, 4999, motor_columns=(0, 1, 2), sample_ms=5.0)
    assert a.pinned_by == (4,)
    assert a.phase_bounds[0] <= 2.2 <= a.phase_bounds[1]
    assert a.drift_bounds[0] <= -300e-6 <= a.drift_bounds[1]
    assert a.phase_bounds[1] - a.phase_bounds[0] <= 5.0 + 0.2  # a sample period, the grid's step
    assert a.drift_bounds[1] - a.drift_bounds[0] < 1.2e-3
