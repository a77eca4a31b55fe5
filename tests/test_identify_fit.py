"""``crslab identify``'s fit: it recovers a plant whose values are known (a recording crslab made of
another arm, sampled like Simulink: 5 ms, an arbitrary start, a drifting clock, 1e-4 steps), and on
the real recording it reproduces the shipped values within their stated uncertainty."""

import sys
from pathlib import Path

import numpy as np
import pytest

from crslab.identify import fit as fitting
from crslab.identify.recording import read_recording
from crslab.identify.runs import lab_offsets
from crslab.plant.model_files import PARAMS
from crslab.plant.plant_params import PlantParams
from crslab.resources import path as resource_path
from crslab.run.api import make_config, simulate

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools" / "benchmarks"))
from real_recording import REAL_RECORDING  # noqa: E402

LAB = resource_path("csrc", "labs", "lab2_square_pid.c")
OTHER_ARM = {"stall_nm1": 13.8, "backemf1": 3.72}  # a weaker, faster-revving waist motor than ours


def simulink_recording(path: Path, plant: PlantParams, *, start_tick: int, phase_ms: float, drift: float,
                       seconds: float) -> Path:
    """What the course's Simulink would record of crslab's arm with ``plant`` running the calibration
    lab: a PlotVar sample every 5 ms of its own clock, showing the last lab() call's values at board
    time start + phase + t (1 + drift), each as int32(10000 v) / 10000."""
    run = simulate(LAB, "hands_off", duration_s=start_tick / 1000 + seconds + 1.0, startup_delay=False,
                   log=True, plant=plant)
    plot = run.log["plot"]
    t = np.round(np.arange(0.0, seconds, 0.005), 6)
    ticks = np.floor(start_tick + phase_ms + t * 1000 * (1 + drift)).astype(int)
    values = np.round(plot[ticks] * 10000) / 10000
    np.savetxt(path, np.column_stack([t, values]), delimiter=",", fmt="%.4f",
               header="t_s,PlotVar1,PlotVar2,PlotVar3,PlotVar4", comments="")
    return path


@pytest.fixture(scope="module")
def other_arm_recording(tmp_path_factory):
    plant = PlantParams.defaults().with_values(OTHER_ARM)
    path = tmp_path_factory.mktemp("identify") / "other_arm.csv"
    return simulink_recording(path, plant, start_tick=5357, phase_ms=0.4, drift=180e-6, seconds=6.0)


@pytest.fixture(scope="module")
def calibration_lab():
    config = make_config(LAB, "hands_off", startup_delay=False)
    return config, lab_offsets(config)


def test_the_calibration_labs_offsets_are_read_from_the_lab(calibration_lab):
    _, offsets = calibration_lab
    assert offsets == pytest.approx((0.0, -0.424, 0.209), abs=1e-7)  # float32 of the file's numbers


def test_identify_recovers_a_known_arm(other_arm_recording, calibration_lab):
    config, offsets = calibration_lab
    source = fitting.Source(read_recording(other_arm_recording), config, offsets)
    result = fitting.fit([source], names=list(OTHER_ARM), jobs=2, max_iterations=15)
    got = {f.name: f.value for f in result.values}
    assert got == pytest.approx(OTHER_ARM, rel=0.03)
    assert all(r < 0.25 * b for r, b in zip(result.rms_after[0], result.rms_before[0]) if b > 1e-3)
    # the alignment found where the recording starts (the lab repeats every 2 s: any period will
    # do) and its clock's drift
    phase = next(f.value for f in result.nuisance if f.name.endswith("phase_ms"))
    assert (result.alignments[0].start_tick + phase) % 2000 == pytest.approx(5357.4 % 2000, abs=1.0)
    drift = next(f.value for f in result.nuisance if f.name.endswith("drift"))
    assert drift == pytest.approx(180e-6, abs=100e-6)  # 100 ppm: 0.6 ms over the 6 s, under a tick
    assert result.plant.value("stall_nm2") == PlantParams.defaults().value("stall_nm2")  # not fitted


UNCERTAINTY_KEYS = {"stall_nm": "stall_nm", "backemf": "backemf_nm_s_per_rad", "coulomb_pos": "Cpos_nm",
                    "coulomb_neg": "Cneg_nm", "viscous_pos": "Vpos_nm_s_per_rad",
                    "viscous_neg": "Vneg_nm_s_per_rad", "static_pos": "Spos_nm", "static_neg": "Sneg_nm",
                    "rotor_inertia": "rotor_kg_m2"}


def stated_uncertainty(name: str) -> float:
    """params.toml's [identified.uncertainty] of a value (95 %)."""
    stem = name.rstrip("0123456789")
    return PARAMS["identified"]["uncertainty"][UNCERTAINTY_KEYS[stem]][int(name[len(stem):]) - 1]


def test_identify_on_the_real_recording_and_table_reproduces_the_shipped_values(calibration_lab):
    """A reduced joint fit (four values of three motors, from 15-25 % off) on
    recordings/lab2_square_pid_real.csv and the course's friction table, as the shipped values were
    found (tools/fit_shipped_plant.py); ``make bench`` runs the full one."""
    from crslab.identify.friction_table import load_table

    config, offsets = calibration_lab
    source = fitting.Source(read_recording(REAL_RECORDING), config, offsets)
    table_file = REAL_RECORDING.parent / "lab3_friction_table_course.toml"
    table = fitting.TableSource(load_table(table_file), str(table_file))
    shipped = PlantParams.defaults()
    names = ["stall_nm1", "rotor_inertia2", "coulomb_neg2", "stall_nm3"]
    start = shipped.with_values({"stall_nm1": 1.2 * shipped.value("stall_nm1"),
                                 "rotor_inertia2": 0.8 * shipped.value("rotor_inertia2"),
                                 "coulomb_neg2": 0.75 * shipped.value("coulomb_neg2"),
                                 "stall_nm3": 0.85 * shipped.value("stall_nm3")})
    result = fitting.fit([source], tables=[table], names=names, start=start, jobs=2, max_iterations=12)
    for f in result.values:
        assert abs(f.value - shipped.value(f.name)) <= stated_uncertainty(f.name), f
    # as close to the recording as the shipped arm, within a third: joint 2's falling steps end
    # just inside the lab's integral window or just outside it, which moves its RMS by that much
    np.testing.assert_array_less(result.rms_after[0], 1.3 * np.array(PARAMS["identified"]["rms_rad"]))
    assert result.tables[0].rms_gap() < 0.1


def test_fit_refuses_what_it_cannot_use(tmp_path, calibration_lab):
    config, offsets = calibration_lab
    still = tmp_path / "still.csv"
    t = np.arange(0, 3, 0.005)
    np.savetxt(still, np.column_stack([t, np.full((len(t), 3), 0.1), np.zeros(len(t))]), delimiter=",",
               header="t,PlotVar1,PlotVar2,PlotVar3,PlotVar4", comments="")
    with pytest.raises(fitting.FitError, match="hardly moves"):
        fitting.fit([fitting.Source(read_recording(still), config, offsets)], names=["stall_nm1"])
    short = read_recording(still).window(0.0, 0.5)
    with pytest.raises(fitting.FitError, match="shorter than a step response"):
        fitting.fit([fitting.Source(short, config, offsets)], names=["stall_nm1"])
    with pytest.raises(fitting.FitError, match="cannot fit 'stall'"):
        fitting.names_to_fit(["stall"], {1, 2, 3})
    assert fitting.names_to_fit(["drive"], {1}) == ["stall_nm1", "backemf1", "drive_lag_s"]
