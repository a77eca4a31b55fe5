"""crslab serve offers the contest (issue 37): a run with ``contest`` on is ``crslab contest``'s run
(the contest world, hands off, the arm resting where the lab's own offsets say, until the arm comes
to rest), and the page gets its scorecard before ``ended``, the egg's force as a scope column, and
a camera that frames the fixtures."""

from __future__ import annotations

import base64
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from serve_server import logged_in, roster_server, run_message

from crslab.serve.app import arm_shapes, fixtures_view
from crslab.serve.page_messages import ProtocolError, parse_message
from crslab.sinks.page_stream import SCOPE_SIGNALS
from crslab.starters import starter_text
from crslab.world import load_world
from crslab.world.layout_checks import fixture_solids
from crslab.world.shapes import Box

FINAL = starter_text("final", "B")


def test_the_run_message_takes_contest_as_a_flag():
    assert parse_message(json.dumps(run_message(FINAL, contest=True)))["contest"] is True
    assert parse_message(json.dumps(run_message(FINAL)))["contest"] is False
    with pytest.raises(ProtocolError, match="contest: must be true or false"):
        parse_message(json.dumps(run_message(FINAL, contest="yes")))


def camera(view):
    """Where arm3d.js puts its camera for ``view``: three.js's spherical offset (y up) turned into
    MuJoCo's frame (z up) around the target."""
    r, phi, theta = view["distance"], view["phi"], view["theta"]
    x, y, z = r * math.sin(phi) * math.sin(theta), r * math.cos(phi), r * math.sin(phi) * math.cos(theta)
    return np.asarray(view["target"]) + (z, x, y)


def test_the_camera_frames_every_fixture():
    world = load_world("contest")
    view = arm_shapes("contest")["view"]
    assert view == fixtures_view(world) and arm_shapes()["view"] is None
    eye, target = camera(view), np.asarray(view["target"])
    axis = (target - eye) / np.linalg.norm(target - eye)
    half = math.radians(view["fov_deg"] / 2)
    solids = fixture_solids(world)
    assert {table for table, _ in solids} == {"hole", "obstacle", "groove", "egg"}
    for table, solid in solids:
        z0, z1 = solid.z_range
        if isinstance(solid, Box):
            xy = solid.corners_xy()
        else:   # an upright cylinder: its rim's points every 10 degrees
            a = np.radians(np.arange(0, 360, 10))
            xy = np.asarray(solid.center_xy) + solid.radius * np.stack([np.cos(a), np.sin(a)], axis=1)
        for corner in [(*p, z) for p in xy for z in (z0, z1)]:
            ray = (np.asarray(corner) - eye) / np.linalg.norm(np.asarray(corner) - eye)
            assert math.acos(np.clip(ray @ axis, -1, 1)) < half, (table, solid.name, corner)


@pytest.fixture(scope="module")
def alice(tmp_path_factory):
    for server in roster_server(tmp_path_factory):
        yield from logged_in(server, "alice")


@pytest.fixture(scope="module")
def contest_run(alice, tmp_path_factory):
    """The final starter with another bench's offsets, run on the page with ``contest`` on (the
    page's world left at none and its scenario at the tour: the contest's own are used)."""
    text = FINAL.replace("float offset_Enc2_rad = -0.42;", "float offset_Enc2_rad = -0.41;")
    assert text != FINAL
    lab = tmp_path_factory.mktemp("contest") / "final.c"
    lab.write_text(text)
    alice.send(run_message(lab, name="final.c", contest=True))
    return lab, alice.until("ended")


def test_a_contest_run_on_the_page_is_crslab_contest_s(contest_run):
    lab, got = contest_run
    started = next(m for m in got if m["type"] == "started")
    assert started["scenario"] == "hands_off"
    assert started["contest"]["band_g"] == [500.0, 1000.0]
    assert started["contest"]["rest_motor_rad"][1:] == pytest.approx([-0.41, 0.24], abs=1e-7)
    [card] = [m for m in got if m["type"] == "scorecard"]
    assert got[-1]["type"] == "ended" and got[-1]["status"] == "ok"
    assert got.index(card) < len(got) - 1    # before ended
    # the run ended when the arm came to rest, not at the 60 s limit
    assert got[-1]["end_tick"] < 60_000 and card["card"]["run"]["still_since_s"] is not None
    # crslab contest's card of the same lab (every tick logged; the page logs every 5th)
    r = subprocess.run([sys.executable, "-m", "crslab", "contest", "--lab", lab, "--json"],
                       capture_output=True, text=True, timeout=600)
    cli = json.loads(r.stdout)
    page = card["card"]
    assert r.returncode == 0 and page["complete"] and cli["complete"]
    assert page["rest"] == cli["rest"] and page["run"]["end_s"] == cli["run"]["end_s"]
    # the first motion and the last task each within a 5 ms row
    assert page["time_s"] == pytest.approx(cli["time_s"], abs=0.011)
    assert page["tasks"]["egg"]["peak_g"] == pytest.approx(cli["tasks"]["egg"]["peak_g"], abs=50)
    assert card["lines"][5].startswith("rest      -0.4100 0.2400 rad: the lab's own offset_Enc2_rad")


def test_the_egg_s_force_is_a_scope_column(contest_run):
    _, got = contest_run
    chunks = [m for m in got if m["type"] == "chunk" and "scope" in m]
    assert {c["scope"]["columns"] for c in chunks} == {len(SCOPE_SIGNALS) + 1}
    scale = {}
    for c in chunks:
        s = c["scope"]
        rows = np.frombuffer(base64.b64decode(s["data"]), "<f4").reshape(s["rows"], s["columns"])
        scale.update({s["tick0"] + i * s["every"]: float(v) for i, v in enumerate(rows[:, -1])})
    # the frames carry the scale's grams too (rounded to 0.1 g): the same at the ticks both have (a
    # chunk cut at its share after too few ticks for a scope row has no frames)
    frames = {f[0]: f[10] for m in got if m["type"] == "chunk" for f in m.get("frames", [])}
    common = sorted(set(scale) & set(frames))
    assert len(common) > 100 and max(scale.values()) > 500
    assert all(abs(scale[t] - frames[t]) <= 0.06 for t in common)
