"""A sweep's variations reach the arm as the same change made another way would: each value of a
sample gives the run that a scenario file, the resting pose or a hand-scaled model gives."""

import dataclasses
import math
from pathlib import Path

import pytest

from crslab.lab.source import LabSource
from crslab.run.api import make_config
from crslab.run.board_run import BoardRun
from crslab.scenario.load import parse_scenario
from crslab.sinks.memory import MemorySink
from crslab.sweep import variations
from crslab.sweep.run_metrics import run_metrics
from crslab.sweep.sample_job import SweepJob, SweepSpec

LAB = Path(__file__).parent / "labs" / "sweep_pd.c"
END_TICK = 600
FINAL = ("theta1motor_final_rad", "theta2motor_final_rad", "theta3motor_final_rad")


@pytest.fixture(scope="module")
def base():
    return make_config(LAB, "hands_off", startup_delay=False)


def swept(base, **values):
    """The row of one sample with ``values`` (names as --vary takes them)."""
    varies = variations.check(
        [variations.parse_vary(f"{k.replace('__', ':')}={v}:{v}") for k, v in values.items()],
        base.build.watched,
        LAB.name,
    )
    spec = SweepSpec(LabSource.read(LAB), base, END_TICK, tuple(varies), seed=3)
    return SweepJob(spec, 0, tuple(float(v) for v in values.values())).run()


def direct(config):
    """The final motor angles of ``config`` run straight through a BoardRun (no sweep)."""
    memory = MemorySink()
    with BoardRun(dataclasses.replace(config, log_signals=True)) as sim:
        result = sim.run(END_TICK, memory)
    m = run_metrics(memory.log, result.stats, startup_ticks=0)
    return tuple(m[k] for k in FINAL)


def scenario(text):
    return parse_scenario("end = 5.0\n" + text, Path("case.toml"))


def final(row):
    assert row["status"] == "ok", row["message"]
    return tuple(row[k] for k in FINAL)


def test_friction_and_payload_are_the_scenario_plant_table(base):
    expected = direct(
        dataclasses.replace(base, scenario=scenario("[plant]\nfriction_scale = 0.3\nend_mass_kg = 1.2\n"))
    )
    assert final(swept(base, friction=0.3, payload_kg=1.2)) == expected
    assert expected != direct(base)  # the change is visible at all


def test_a_watched_variable_is_written_before_the_first_tick(base):
    events = '[[event]]\nat = 0\nkind = "set"\nvar = "target2"\nvalue = 0.35\n'
    expected = direct(dataclasses.replace(base, scenario=scenario(events)))
    assert final(swept(base, var__target2=0.35)) == expected
    events = '[[event]]\nat = 0\nkind = "set"\nvar = "gains"\nindex = 0\nvalue = 0.5\n'
    assert final(swept(base, **{"var__gains[0]": 0.5})) == direct(
        dataclasses.replace(base, scenario=scenario(events))
    )


def test_the_true_resting_pose_is_the_runs(base):
    expected = direct(dataclasses.replace(base, rest_motor_rad=(0.0, -0.38, 0.3)))
    assert final(swept(base, rest_offset2=-0.38, rest_offset3=0.3)) == expected


def test_motor_gain_scales_the_torque_the_arm_feels(base):
    """Joint 1 under an open-loop torque: gain 0.5 with 2 units moves it as gain 1 with 1 unit."""
    half = swept(base, motor_gain=0.5, var__tau1_open=2.0, var__Kp2=0.0, var__Kd2=0.0)
    full = swept(base, motor_gain=1.0, var__tau1_open=1.0, var__Kp2=0.0, var__Kd2=0.0)
    assert final(half)[0] == pytest.approx(final(full)[0], abs=1e-9) and abs(final(full)[0]) > 0.05
    assert (
        final(half)[0]
        != final(swept(base, motor_gain=1.0, var__tau1_open=2.0, var__Kp2=0.0, var__Kd2=0.0))[0]
    )


def test_per_motor_friction_multiplies_the_overall_scale(base):
    """Motor 1 at 2 x 0.5 = 1: joint 1 moves as with no change, and not as with motor 1 at 0.5
    (motors 2 and 3 get no torque: friction holds them at rest either way)."""
    push = {"var__tau1_open": 1.0, "var__Kp2": 0.0, "var__Kd2": 0.0, "var__gains[1]": 0.0}
    same = swept(base, friction=2.0, friction1=0.5, **push)
    assert final(same)[0] == final(swept(base, friction=1.0, **push))[0]
    assert final(swept(base, friction1=0.5, **push))[0] != final(same)[0]


def test_mass_scales_the_links_and_not_the_payload(base):
    config = dataclasses.replace(base, plant=base.plant.with_values({"mass": 1.5}))
    assert final(swept(base, mass=1.5)) == direct(config)
    from crslab.plant.model import apply_plant, load_model

    model = load_model()
    masses = model.body_mass.copy()
    apply_plant(model, base.plant.with_values({"mass": 1.5}))
    payload = model.body("payload").id
    assert model.body_mass[payload] == masses[payload]
    assert model.body_mass[model.body("forearm").id] == pytest.approx(1.5 * 1.14)
    assert model.body_subtreemass[0] == pytest.approx(1.5 * (4 + 1.3 + 1.14) + masses[payload])


def test_encoder_noise_is_seeded_per_sample(base):
    varies = variations.check(
        [variations.parse_vary("encoder_noise_counts=0:100")], base.build.watched, LAB.name
    )
    spec = SweepSpec(LabSource.read(LAB), base, END_TICK, tuple(varies), seed=3)
    a, b, c = (SweepJob(spec, s, (80.0,)).run() for s in (4, 4, 5))
    assert final(a) == final(b) != final(c)
    assert final(a) != final(swept(base, encoder_noise_counts=0.0))


def test_unknown_names_list_the_valid_ones(base):
    with pytest.raises(variations.VaryError) as e:
        variations.check([variations.parse_vary("frictoin=0:1")], base.build.watched, LAB.name)
    assert str(e.value).startswith("--vary frictoin: unknown name; valid: friction, friction1, friction2, ")
    assert "var:Kp2, var:Kd2, var:target2, var:tau1_open, var:steps, var:gains[i]" in str(e.value)
    with pytest.raises(variations.VaryError, match=r"Kq is not a watched .* of sweep_pd.c \(watched: Kp2, "):
        variations.check([variations.parse_vary("var:Kq=0:1")], base.build.watched, LAB.name)
    with pytest.raises(
        variations.VaryError, match=r"gains has 2 elements in sweep_pd.c: give an index 0..1"
    ):
        variations.check([variations.parse_vary("var:gains=0:1")], base.build.watched, LAB.name)
    with pytest.raises(variations.VaryError, match="friction must be within 0 .. inf"):
        variations.check([variations.parse_vary("friction=-1:1")], base.build.watched, LAB.name)
    [steps] = variations.check([variations.parse_vary("var:steps=1:4")], base.build.watched, LAB.name)
    assert steps.integer and steps.value_at(0.4) == 2.0 and not math.isnan(steps.value_at(1.0))
