"""crslab serve and the world: the page may choose a built-in world (none by default, contest), the
3D view gets that world's fixtures (which a hand cannot drag) and the peg's wrist, and a run in
it is crslab sim's in the same world, each frame carrying the egg's force, the scale and the egg's
state."""

from __future__ import annotations

import json

import pytest
from serve_server import logged_in, roster_server, run_message, serial_of

from crslab.run.api import simulate
from crslab.serve.app import arm_shapes
from crslab.serve.page_messages import ProtocolError, parse_message
from crslab.starters import starter_text

LAB_A = starter_text("lab1", "A")


def test_the_run_message_takes_a_builtin_world_only():
    msg = run_message(LAB_A, world="contest")
    assert parse_message(json.dumps(msg))["world"] == "contest"
    assert parse_message(json.dumps(run_message(LAB_A)))["world"] == "none"
    with pytest.raises(ProtocolError, match="world: must be one of none, contest"):
        parse_message(json.dumps(run_message(LAB_A, world="/etc/passwd")))


def test_the_3d_view_gets_the_worlds_fixtures_and_the_pegs_wrist():
    bodies = {b["name"]: b for b in arm_shapes("contest")["bodies"]}
    assert {"hole", "obstacle", "groove", "egg", "scale", "table", "peg"} <= set(bodies)
    assert [n for n, b in bodies.items() if b["moving"]] == ["waist", "upper_arm", "forearm"]
    assert bodies["peg"]["joint"]["q"] is None and bodies["peg"]["joint"]["minus_sum"] == [1, 2]
    assert [s["kind"] for s in bodies["egg"]["shapes"]] == ["ellipsoid"]
    free = {b["name"] for b in arm_shapes()["bodies"]}
    assert not free & {"hole", "egg", "peg", "table"} and {"waist", "upper_arm", "forearm"} <= free


@pytest.fixture(scope="module")
def alice(tmp_path_factory):
    for server in roster_server(tmp_path_factory):
        yield from logged_in(server, "alice")


def test_a_run_in_the_contest_world_is_crslab_sims_there(alice, tmp_path):
    lab = tmp_path / "lab.c"
    lab.write_text(LAB_A)
    alice.send(run_message(lab, duration=5.0, scenario={"name": "hands_off"}, world="contest"))
    got = alice.until("ended")
    assert got[-1]["status"] == "ok", got[-1]
    frames = [f for m in got if m["type"] == "chunk" for f in m.get("frames", [])]  # (none if no row)
    assert {len(f) for f in frames} == {12}  # tick, 3 DH, 3 motor, safety, board, egg N, scale g, broken
    assert all(f[9] == 0 and f[10] == 0 and f[11] == 0 for f in frames)  # nothing presses the egg
    assert serial_of(got) == simulate(lab, "hands_off", duration_s=5.0, world="contest").sent


def test_the_hand_on_the_page_pulls_the_arm_in_the_contest_world(alice):
    """The hand's force goes to the world's scene (more bodies than the bare arm's): dragging the
    forearm's end 15 cm up raises it, as in free air (in the contest world the forearm ends at the
    wrist, the arm's height above the peg's tip that the course's kinematics names)."""
    import numpy as np

    from crslab import crs
    from crslab.world import load_world

    alice.send(run_message(LAB_A, scenario={"name": "hands_off"}, speed=4.0, duration=8.0, world="contest"))
    got = alice.until("chunk")
    start = got[-1]["frames"][-1]
    tip = crs.fk(crs.dh_to_motor(np.array(start[1:4]))) * crs.M_PER_IN
    alice.send(
        {
            "type": "hand",
            "body": "forearm",
            "anchor": [0.254, 0.0, 0.0],
            "target": (tip + [0, 0, load_world("contest").arm_raised_m + 0.15]).tolist(),
        }
    )
    frames = []
    while not frames or frames[-1][0] < start[0] + 1500:
        frames += alice.next().get("frames", [])
    alice.send({"type": "release"})
    alice.send({"type": "stop"})
    ended = alice.until("ended")[-1]
    assert ended["status"] in ("ok", "interrupted"), ended
    assert np.array(frames[-1][4:7])[2] - start[6] < -0.2  # motor 3 turned the forearm up
