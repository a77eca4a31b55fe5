"""``make bench``'s baselines are honest: the bare C ``mj_step`` loop and ``mujoco.rollout``,
replaying the controls and forces recorded from a crslab run, end in that run's state bit for
bit (they do its physics, not an easier one); the scopes benchmark finds the ``--json`` summary
whatever stderr lines surround it. (The benchmarks' timings are ``make bench``'s, not tested.)"""

import sys
from pathlib import Path

import numpy as np
import pytest

from crslab.run.api import make_config

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools" / "benchmarks"))
import baselines  # noqa: E402
from bench_scopes import json_summary  # noqa: E402

TICKS = 12_000  # the tour to 12 s: the hand takes the arm out of the envelope (11 s), the hold pushes back


@pytest.fixture(scope="module")
def recording():
    return baselines.record_run(make_config(), TICKS)


def test_the_recording_holds_the_hands_forces_and_the_frameworks_commands(recording):
    assert recording.ctrl.shape == (TICKS, 3) and recording.qfrc_applied.shape == (TICKS, 3)
    assert np.all(recording.qfrc_applied[:5000] == 0) and np.abs(recording.qfrc_applied[5000:]).max() > 5
    assert np.abs(recording.ctrl).max() > 0.5  # the framework holds the arm back outside the envelope
    # the rest pose in DH angles: q2 = th2M - pi/2, q3 = th3M - q2 (motor 3 reads the forearm's angle)
    np.testing.assert_allclose(recording.qpos0, [0.0, -0.42 - np.pi / 2, 0.24 + 0.42 + np.pi / 2], atol=1e-12)


def test_the_bare_c_loop_replays_the_run_bit_for_bit_and_would_notice_other_physics(recording, tmp_path):
    exe = baselines.build_bare_loop(tmp_path)
    run = baselines.run_bare_loop(exe, recording.save(tmp_path / "controls.bin"), passes=2)
    assert run.ticks == TICKS and len(run.pass_s) == 2 and all(s > 0 for s in run.pass_s)
    assert len(run.cpu_s) == 2 and all(s > 0 for s in run.cpu_s)
    baselines.same_physics(recording, run.qpos_end, run.qvel_end, "the bare C loop")
    no_hand = baselines.Recording(recording.qpos0, recording.ctrl, 0 * recording.qfrc_applied,
                                  recording.qpos_end, recording.qvel_end)
    other = baselines.run_bare_loop(exe, no_hand.save(tmp_path / "no_hand.bin"), passes=1)
    with pytest.raises(AssertionError, match="did not do the recorded run's physics"):
        baselines.same_physics(recording, other.qpos_end, other.qvel_end, "the bare C loop")


def test_mujoco_rollout_replays_the_run_bit_for_bit(recording):
    seconds, qpos, qvel = baselines.rollout_run(recording)
    assert seconds > 0
    baselines.same_physics(recording, qpos, qvel, "mujoco.rollout")


def test_the_json_summary_is_found_among_announcements_and_warnings():
    stderr = ('crslab sim: serial port on /dev/pts/3\n{"status": "ok", "wall_s": 0.61, "lab_calls": 3}\n'
              "crslab sim: warning: lab.c's slowest lab() call took 900 us, close to the 1000 us budget\n")
    assert json_summary(stderr) == {"status": "ok", "wall_s": 0.61, "lab_calls": 3}
    with pytest.raises(ValueError, match="no --json summary"):
        json_summary("crslab sim: {not json}\n[1, 2]\n")


def test_the_paced_loop_steps_each_run_by_whole_chunks_as_due_and_does_the_runs_physics(recording, tmp_path):
    """Two runs on one core, 0.33 s paced as a run host paces (250-tick chunks, wake-ups 60 ms
    apart from the start): wake-ups at 0, 60, ..., 300 ms each run every chunk due before the next
    one (360 ms). Run 0's chunks are due at 0 and 250 ms (two); run 1's at 0.618 x 250 = 155 ms and
    405 ms (one). Run 0 started at the recording's first tick: after its 500 steps it is where
    MuJoCo stepping the same 500 ticks of controls and forces puts it, bit for bit."""
    import mujoco

    from crslab.run.pacing import PAGE_CHUNKS
    from crslab.serve.run_host import BATCH_S

    assert (PAGE_CHUNKS.realtime_ticks, BATCH_S) == (250, 0.06)  # the counts below are for these
    exe = baselines.build_bare_loop(tmp_path, source=baselines.PACED_C)
    run = baselines.run_paced_loops(exe, recording.save(tmp_path / "controls.bin"), {0: 2}, 0.33)
    assert run.steps == 3 * 250 and run.cpu_s > 0 and run.us_per_step > 0
    model = mujoco.MjModel.from_xml_path(str(baselines.MODEL_XML))
    data = mujoco.MjData(model)
    data.qpos[:] = recording.qpos0
    mujoco.mj_forward(model, data)
    for k in range(500):
        data.ctrl[:] = recording.ctrl[k]
        data.qfrc_applied[:] = recording.qfrc_applied[k]
        mujoco.mj_step(model, data)
    assert np.array_equal(run.qpos_first[0], data.qpos)
