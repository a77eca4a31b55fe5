"""A contest run as a TA runs one (crslab/contest/run.py): the arm rests where the lab's own offsets
say, and the run lasts until the arm comes to rest after its last motion, or ``--duration``, or
(a lab that never moves the arm) 15 s after lab()'s first call. Real runs of crslab's own final
project (``crslab new final``) and of test labs; each number is the rule's own."""

import numpy as np
import pytest

from crslab import crs
from crslab.contest.motion import NO_MOTION_S, STILL_S
from crslab.contest.offsets import contest_rest
from crslab.contest.run import CHUNK_TICKS, CONTEST_SCENARIO, contest_config, run_contest
from crslab.contest.scorecard import RunFacts, score
from crslab.framework_facts import STARTUP_TICKS, TICKS_PER_S
from crslab.run.api import make_config
from crslab.starters import starter_text
from crslab.world import WorldError, load_world
from tests.test_contest_offsets import GEN_B, LAB

STARTER = starter_text("final", "B")
WORLD = load_world("contest")


def contest(lab, text, duration_s=None, offsets=None):
    rest = contest_rest(text, offsets)
    config = contest_config(make_config(lab, CONTEST_SCENARIO, world=WORLD), rest)
    result = run_contest(config, duration_s=duration_s)
    return result, rest, score(result.log, WORLD, RunFacts(result.status, result.message, result.end_tick,
                                                           result.stats, rest, config.startup_ticks))


@pytest.fixture(scope="module")
def own_offsets(tmp_path_factory):
    """The starter with its offsets changed to another bench's: -0.40 and 0.26 rad."""
    text = STARTER.replace("float offset_Enc2_rad = -0.42;", "float offset_Enc2_rad = -0.40;").replace(
        "float offset_Enc3_rad = 0.24;", "float offset_Enc3_rad = 0.26;")
    assert text != STARTER and "-0.40;" in text and "0.26;" in text
    lab = tmp_path_factory.mktemp("offsets") / "final.c"
    lab.write_text(text)
    return contest(lab, text)


def test_the_lab_s_own_offsets_are_where_the_arm_rests(own_offsets):
    result, rest, card = own_offsets
    assert rest.source == "lab" and rest.motor_rad[1:] == pytest.approx((-0.40, 0.26), abs=1e-7)
    # the first row: the plant's true angles (as motor angles) are the offsets, and the encoders
    # read them exactly (the lab calibrated to this bench)
    true = crs.dh_to_motor(np.asarray(result.log["qpos_dh_rad"][0], float))
    assert true[1:] == pytest.approx(rest.motor_rad[1:], abs=1e-9)   # the C floats nearest -0.40 and 0.26
    assert np.asarray(result.log["enc_rad"][0], float)[1:] == pytest.approx((-0.40, 0.26), abs=1e-6)
    assert "rest      -0.4000 0.2600 rad: the lab's own offset_Enc2_rad, offset_Enc3_rad" in card.lines()[5]


def test_the_run_ends_once_the_arm_has_come_to_rest(own_offsets):
    result, _, card = own_offsets
    assert result.status == "ok" and card.complete
    still = card.ended.still_since_s
    end_s = result.end_tick / TICKS_PER_S
    # the run looks after every chunk: it ended at the first chunk's end at least STILL_S after
    # the arm came to rest
    assert still is not None and STILL_S <= end_s - still < STILL_S + CHUNK_TICKS / TICKS_PER_S
    assert result.end_tick % CHUNK_TICKS == 0 and end_s < 60.0
    assert card.lines()[6] == f"run       ended at t = {end_s:.2f} s: the arm at rest since t = {still:.2f} s"


def test_a_duration_is_run_to_its_end(tmp_path):
    lab = tmp_path / "final.c"
    lab.write_text(STARTER)
    result, _, card = contest(lab, STARTER, duration_s=8.0)
    assert result.end_tick == 8000 and len(result.log["tick"]) == 8000
    assert card.lines()[6] == "run       ended at t = 8.00 s"


def test_a_lab_that_never_moves_the_arm_is_given_15_s(tmp_path):
    text = GEN_B + "float offset_Enc2_rad = -0.42;\nfloat offset_Enc3_rad = 0.24;\n" + LAB
    lab = tmp_path / "still.c"
    lab.write_text(text)
    result, _, card = contest(lab, text)
    limit = STARTUP_TICKS + NO_MOTION_S * TICKS_PER_S
    assert limit <= result.end_tick < limit + CHUNK_TICKS
    end_s = result.end_tick / TICKS_PER_S
    assert card.lines()[6] == f"run       ended at t = {end_s:.2f} s: the arm never moved"


def test_offsets_that_rest_the_arm_in_a_fixture_are_refused(tmp_path):
    lab = tmp_path / "final.c"
    lab.write_text(STARTER)
    config = make_config(lab, CONTEST_SCENARIO, world=WORLD)
    # motor angles that put the peg's tip 5 mm into the groove plate's solid top (crslab ik), the
    # waist at 0 as at rest: the first point along y = 0 that the plate's solids hold
    from crslab.world.layout_checks import fixture_solids

    top = WORLD.groove.top_z_m - 0.005
    plate = [shape for table, shape in fixture_solids(WORLD) if table == "groove"]
    x = next(x for x in np.arange(0.30, 0.50, 0.001) if any(p.distance(np.array([[x, 0.0, top]]))[0] == 0
                                                            for p in plate))
    q = crs.ik(np.array([x, 0.0, top]) / crs.M_PER_IN, elbow="up")
    with pytest.raises(WorldError) as err:
        contest_config(config, contest_rest(STARTER, (q[1], q[2])))
    assert str(err.value).startswith(f"the arm resting at {q[1]:.4f} {q[2]:.4f} rad (--offsets): ")
    assert "groove plate" in str(err.value) and "\n" not in str(err.value)
