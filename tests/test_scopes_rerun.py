"""--rrd: a run's rerun recording, read back with rerun's own API, holds what Simulink and Tera Term saw."""

import math
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest
from rerun.chunk import RrdReader

from crslab import crs

ROOT = Path(__file__).resolve().parents[1]
DURATION_S = 8.0  # the tour: rest, then by 7 s held at motor zero
PRINT_TICKS = list(range(4100, 8000, 500))


def crslab_sim(*args):
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--no-stdin", "--duration",
                        str(DURATION_S), *map(str, args)], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("rrd")
    crslab_sim("--rrd", tmp / "run.rrd", "--transcript", tmp / "scoped.bin", "--csv", tmp / "run.csv",
               "--pty")
    crslab_sim("--transcript", tmp / "plain.bin")
    reader = RrdReader(tmp / "run.rrd")
    entities = {}
    for chunk in reader.stream():  # static data under "<entity> static", timed data under "<entity>"
        key = chunk.entity_path + (" static" if chunk.is_static else "")
        entities.setdefault(key, []).append(pa.Table.from_batches([chunk.to_record_batch()]))
    return tmp, reader, {e: pa.concat_tables(t, promote_options="default") for e, t in entities.items()}


def timed(table, component):
    """(ticks, values) of a component logged on the sim_time timeline, in time order."""
    ticks = table["sim_time"].cast(pa.int64()).to_numpy() // 1_000_000
    order = np.argsort(ticks, kind="stable")
    values = table[component].to_pylist()
    return ticks[order], [values[i] for i in order]


def printed(tmp):
    """The Tera Term lines of the run, three per print."""
    return (tmp / "plain.bin").read_bytes().decode().split("\n\r")[:-1]


def test_scopes_and_the_pty_do_not_change_the_transcript(recorded):
    tmp, _, _ = recorded
    assert (tmp / "scoped.bin").read_bytes() == (tmp / "plain.bin").read_bytes()


def test_recording_holds_the_expected_entities_and_a_blueprint(recorded):
    _, reader, entities = recorded
    for entity in ["/scopes/simulink", "/scopes/motor_angle", "/scopes/torque/lab", "/scopes/torque/applied",
                   "/scopes/digital", "/serial", "/arm/waist", "/arm/upper_arm", "/arm/forearm",
                   "/arm/upper_arm/shapes/capsule static", "/arm/forearm/shapes/capsule static",
                   "/arm/world/shapes/cylinder static", "/scopes/simulink static"]:
        assert entity in entities, sorted(entities)
    assert len(reader.recordings()) == 1 and len(reader.blueprints()) == 1
    lengths = entities["/arm/forearm/shapes/capsule static"]["Capsules3D:lengths"].to_pylist()
    assert np.allclose(lengths, [[0.254]])  # the forearm: 10 in, from the MuJoCo model
    names = entities["/scopes/simulink static"]["SeriesLines:names"].to_pylist()
    assert names == [[f"Simulink_PlotVar{k}" for k in range(1, 5)]]


def test_one_simulink_sample_per_5_ms_quantized_as_simulink_receives_them(recorded):
    _, _, entities = recorded
    ticks, values = timed(entities["/scopes/simulink"], "Scalars:scalars")
    assert ticks.tolist() == list(range(0, 8000, 5))
    values = np.array(values)
    assert values.shape == (1600, 4)
    assert np.allclose(values * 10000, np.round(values * 10000), atol=1e-6)  # steps of 1e-4
    assert not values[ticks < 4100].any()  # lab() has not run yet: the variables are still 0


def test_simulink_and_scopes_agree_with_the_printed_values(recorded):
    tmp, _, entities = recorded
    lines = printed(tmp)
    assert len(lines) == 3 * len(PRINT_TICKS)
    s_ticks, s_values = timed(entities["/scopes/simulink"], "Scalars:scalars")
    m_ticks, m_values = timed(entities["/scopes/motor_angle"], "Scalars:scalars")
    for k, tick in enumerate(PRINT_TICKS):
        motor_deg = [float(v) for v in lines[3 * k].split()]
        xyz_in = [float(v) for v in lines[3 * k + 1].split()]
        plot = s_values[int(np.searchsorted(s_ticks, tick))]  # Lab 1 plots theta1..3motor and z
        # Lab 1 is a Gen A lab: its printf truncates, so a printed %.2f is up to 0.01 off
        np.testing.assert_allclose(np.degrees(plot[:3]), motor_deg, atol=0.01 + np.degrees(1e-4))
        assert abs(plot[3] - xyz_in[2]) <= 0.01 + 1e-4
        motor = m_values[int(np.searchsorted(m_ticks, tick))]  # every tick, what lab() received
        np.testing.assert_allclose(np.degrees(motor), motor_deg, atol=0.01 + 1e-5)
        np.testing.assert_allclose(crs.fk(np.array(motor)), xyz_in, atol=0.01 + 1e-5)


def test_serial_lines_are_the_transcript_at_the_tick_they_reach_tera_term(recorded):
    tmp, _, entities = recorded
    ticks, text = timed(entities["/serial"], "TextLog:text")
    lines = printed(tmp)
    assert [t[0] for t in text] == lines
    # each print's three lines leave an idle serial line at 11.52 characters per ms: a line shows
    # in the tick during which its "\n" has left (character c leaves at c * 10 bits / 115200 baud)
    want = []
    for k, tick in enumerate(PRINT_TICKS):
        before = 0
        for line in lines[3 * k:3 * k + 3]:
            newline = before + len(line) + 1
            want.append(tick + math.ceil(Fraction(newline * 10, 115200) * 1000) - 1)
            before += len(line) + 2
    assert ticks.tolist() == want


def test_every_tick_has_motor_angles_torques_and_the_safety_flag(recorded):
    _, _, entities = recorded
    for entity, width in [("/scopes/motor_angle", 3), ("/scopes/torque/lab", 3),
                          ("/scopes/torque/applied", 3), ("/scopes/digital", 4)]:
        ticks, values = timed(entities[entity], "Scalars:scalars")
        assert ticks.tolist() == list(range(8000)) and {len(v) for v in values} == {width}
    _, digital = timed(entities["/scopes/digital"], "Scalars:scalars")
    digital = np.array(digital)
    assert set(np.unique(digital)) <= {0.0, 1.0}
    # Lab 1 toggles both LEDs at every print: each print tick flips GPIO34 and GPIO60
    for led in (1, 2):
        assert (np.flatnonzero(np.diff(digital[:, led])) + 1).tolist() == PRINT_TICKS


def test_the_arm_moves_in_3d_from_rest_to_motor_zero(recorded):
    _, _, entities = recorded
    ticks, pos = timed(entities["/arm/forearm"], "Transform3D:translation")
    assert ticks.tolist() == list(range(0, 8000, 10))
    pos = np.array(pos)[:, 0]  # one translation per row
    # the elbow (the forearm's frame): at rest per the DH FK of the rest pose, at motor zero 20 in up
    dh_rest = crs.motor_to_dh([0.0, -0.42, 0.24])
    elbow_rest = 0.254 * np.array([np.cos(dh_rest[1]), 0.0, 1 - np.sin(dh_rest[1])])
    np.testing.assert_allclose(pos[0], elbow_rest, atol=1e-6)
    np.testing.assert_allclose(pos[ticks.tolist().index(7900)], [0.0, 0.0, 0.508], atol=2e-3)
