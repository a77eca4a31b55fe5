"""``crslab identify`` with several experiments: friction tables (the course's Lab 3 method) beside
recordings, each weighed by its uncertainty, and the cross-validation that fits each alone."""

import numpy as np
import pytest
from test_identify_fit import LAB, simulink_recording

from crslab.identify import fit as fitting
from crslab.identify.cross_validation import cross_validate, cross_validation_lines
from crslab.identify.friction_table import FrictionTable, load_table, predict
from crslab.identify.recording import read_recording
from crslab.identify.runs import Runner, lab_offsets
from crslab.plant.plant_params import PlantParams
from crslab.run.api import make_config

SHIPPED = PlantParams.defaults()
OTHER = {"stall_nm1": 18.0, "coulomb_pos1": 1.25 * SHIPPED.value("coulomb_pos1"),
         "coulomb_neg1": 1.25 * SHIPPED.value("coulomb_neg1")}
"""Another arm: a weaker waist motor with a quarter more friction."""


def table_of(plant: PlantParams, uncertainty: float = 0.02) -> fitting.TableSource:
    """What the course's method would measure on ``plant``, as a table source."""
    t = predict(plant)
    return fitting.TableSource(FrictionTable(t.rows, t.speeds_rad_s, uncertainty, "test"), "other_arm.toml")


def test_a_table_alone_recovers_the_friction_it_was_measured_on():
    other = SHIPPED.with_values({"coulomb_pos2": 3.4, "viscous_neg3": 1.0, "coulomb_neg1": -2.2})
    result = fitting.fit([], tables=[table_of(other)], names=["friction"], start=SHIPPED)
    got = {f.name: f.value for f in result.values}
    for name in ("coulomb_pos2", "viscous_neg3", "coulomb_neg1", "viscous_pos1"):
        assert got[name] == pytest.approx(other.value(name), rel=0.005), name
    # the static values were not fitted: they keep their gap to the Coulomb value they go with
    assert result.plant.value("static_pos2") - result.plant.value("coulomb_pos2") == pytest.approx(
        SHIPPED.value("static_pos2") - SHIPPED.value("coulomb_pos2"), abs=1e-9)
    assert result.tables[0].rms_gap(after=True) < 1e-3 < result.tables[0].rms_gap(after=False)
    assert result.runs == 0 and result.rms_after == []  # nothing ran: a table is predicted, not simulated


def test_a_table_alone_cannot_fit_the_drive():
    with pytest.raises(fitting.FitError, match="a friction table tells only friction"):
        fitting.fit([], tables=[table_of(SHIPPED)], names=["drive"])
    with pytest.raises(fitting.FitError, match="nothing to fit to"):
        fitting.fit([], names=["friction"])


def test_each_experiment_is_weighed_by_its_uncertainty():
    """A table's residual is (predicted - tabled) over its uncertainty times the number: 1 per
    uncertainty off. (The other arm's friction is ours moved up by 0.2 N.m moving positive, its
    static band's edge with it: only its Cpos1 differs.)"""
    other = SHIPPED.with_values({"coulomb_pos1": SHIPPED.value("coulomb_pos1") + 0.2,
                                 "static_pos1": SHIPPED.value("static_pos1") + 0.2})
    tight, loose = table_of(other, 0.01), table_of(other, 0.04)
    with Runner(1) as runner:
        residuals = [fitting.Problem([], ["coulomb_pos1"], SHIPPED, runner, tables=[t]).residual(
            np.array([SHIPPED.value("coulomb_pos1")])) for t in (tight, loose)]
    numbers = tight.numbers()
    cpos1 = numbers.index((1, "Cpos"))
    gap = predict(SHIPPED).value(1, "Cpos") / tight.table.value(1, "Cpos") - 1.0  # about -9 %
    assert gap == pytest.approx(-0.2 / (6 * tight.table.value(1, "Cpos")), rel=1e-3)
    assert residuals[0][cpos1] == pytest.approx(gap / 0.01, rel=1e-6)
    assert residuals[1][cpos1] == pytest.approx(gap / 0.04, rel=1e-6)
    assert np.count_nonzero(np.abs(residuals[0]) > 1e-6) == 1  # only Cpos1 differs


@pytest.fixture(scope="module")
def joint_fit(tmp_path_factory):
    plant = SHIPPED.with_values(OTHER)
    path = tmp_path_factory.mktemp("joint") / "other_arm.csv"
    recording = simulink_recording(path, plant, start_tick=4321, phase_ms=0.6, drift=120e-6, seconds=4.0)
    config = make_config(LAB, "hands_off", startup_delay=False)
    source = fitting.Source(read_recording(recording), config, lab_offsets(config))
    table = table_of(plant)
    result = fitting.fit([source], tables=[table], names=list(OTHER), jobs=2, max_iterations=10)
    return source, table, result


def test_a_recording_and_a_table_fit_together(joint_fit):
    source, table, result = joint_fit
    got = {f.name: f.value for f in result.values}
    assert got == pytest.approx(OTHER, rel=0.03)
    assert result.tables[0].rms_gap() < 0.01 and result.tables[0].rms_gap(after=False) > 0.05
    assert all(a < 0.3 * b for a, b in zip(result.rms_after[0], result.rms_before[0]) if b > 1e-3)


def test_cross_validation_fits_each_experiment_alone_and_predicts_the_others(joint_fit):
    """The table alone finds the friction but not the waist's weaker motor (it cannot see the
    drive), so it predicts the recording worse than the joint fit does; the recording alone finds
    both. Each row's own cell is that fit's own residual."""
    source, table, joint = joint_fit
    rows = cross_validate([source], [table], names=list(OTHER), start=SHIPPED, joint=joint, jobs=2,
                          max_iterations=10)
    cell = {(p.fitted_on, p.experiment): p for p in rows}
    rec, tab = source.name, table.name
    assert cell[(tab, tab)].own and cell[(tab, tab)].value < 0.005
    assert cell[(tab, rec)].value > 3 * cell[("all together", rec)].value
    joint_rms = float(np.sqrt(np.mean(joint.rms_after[0] ** 2)))
    assert cell[("all together", rec)].value == pytest.approx(joint_rms)
    assert cell[(rec, tab)].value < 0.05  # the recording sees the waist's friction too
    lines = cross_validation_lines(rows)
    assert lines[0].startswith("cross-validation") and len(lines) == 2 + 3
    assert "(own)" in lines[2] and "%" in lines[3]


def test_the_course_table_file_reads_as_the_course_published_it():
    course = load_table(fitting.__file__.replace("crslab/identify/fit.py", "models/crs_arm/recordings/"
                                                 "lab3_friction_table_course.toml"))
    assert course.value(1, "Vpos") == 0.2513 and course.value(2, "Cneg") == -0.5031
    assert course.value(3, "Cpos") == 0.5339 and course.uncertainty == 0.05
