"""--viewer and --rerun: without a display one line says so and the run goes on; with one (a virtual
X server, when Xvfb is installed) MuJoCo's viewer follows the arm and a mouse drag pushes it."""

import os
import subprocess
import sys
from pathlib import Path

import pytest
from waiting import LineWatcher

ROOT = Path(__file__).resolve().parents[1]


def headless_env():
    return {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}


def test_without_a_display_viewer_and_rerun_say_so_in_one_line_and_the_run_goes_on(tmp_path):
    transcript = tmp_path / "t.bin"
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--duration", "5", "--no-stdin",
                        "--viewer", "--rerun", "--transcript", str(transcript)], cwd=ROOT, env=headless_env(),
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    notes = sorted(line for line in r.stderr.splitlines() if "no display" in line)
    assert len(notes) == 2 and notes[1].startswith("crslab sim: --viewer: no display")
    assert notes[0].startswith("crslab sim: --rerun: no display") and "--rrd FILE" in notes[0]
    assert transcript.read_bytes().count(b"\n\r") == 6 and r.stdout.count("\n") == 6


DRAG = """
import mujoco, numpy as np
from crslab import crs
from crslab.live.viewer import MujocoViewer
from crslab.run.api import make_config
from crslab.run.board_run import BoardRun
from crslab.sinks.sink import FanOut, Sink

config = make_config(scenario="hands_off", log=True)
with BoardRun(config) as sim:
    viewer = MujocoViewer(crs.motor_to_dh(config.rest_motor_rad))
    assert viewer.start()
    rows = []
    class Rows(Sink):
        def on_log(self, columns):
            rows.append(columns["qpos_dh_rad"][-1].copy())
    out = FanOut([viewer, Rows()])
    sim.run(1000, out, speed=4.0, controls=[viewer])
    forearm = viewer.model.body("forearm").id
    assert np.allclose(viewer.data.qpos, rows[-1])  # the viewer shows the worker's arm
    with viewer.handle.lock():  # what a Ctrl + right-drag on the forearm sets: pull it 0.3 m up
        pert = viewer.handle.perturb
        pert.select, pert.active = forearm, int(mujoco.mjtPertBit.mjPERT_TRANSLATE)
        pert.localpos[:] = 0
        pert.localmass = 2.0
        pert.refselpos[:] = viewer.data.xpos[forearm] + [0, 0, 0.3]
        pert.refpos[:] = pert.refselpos
        pert.refquat[:] = viewer.data.xquat[forearm]
    sim.run(2000, out, speed=4.0, controls=[viewer])
    viewer.close()
    print(viewer._sent[forearm][2], rows[0][1], rows[-1][1])
"""


@pytest.mark.requires("Xvfb")
def test_with_a_display_a_mouse_drag_in_mujocos_viewer_pushes_the_simulated_arm(tmp_path):
    ready_r, ready_w = os.pipe()  # Xvfb writes its display number here once it accepts clients
    xvfb = subprocess.Popen(["Xvfb", "-displayfd", str(ready_w), "-screen", "0", "800x600x24",
                             "-nolisten", "tcp"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            pass_fds=(ready_w,))
    os.close(ready_w)
    ready = LineWatcher(os.fdopen(ready_r), "Xvfb's -displayfd pipe")
    try:
        number = ready.wait_for(r"^\d+$")[-1].strip()
        r = subprocess.run([sys.executable, "-c", DRAG], cwd=ROOT, capture_output=True, text=True,
                           env={**headless_env(), "DISPLAY": f":{number}"}, timeout=120)
    finally:
        xvfb.kill()
        xvfb.wait()
        ready.all()  # the pipe closed with Xvfb
    assert r.returncode == 0, r.stderr
    up_force_n, th2_before, th2_after = map(float, r.stdout.split())
    assert up_force_n > 10  # the drag became an upward force on the forearm in the worker...
    assert th2_after > th2_before + 0.05  # ...which lifted the upper arm against the friction


def test_the_viewer_opens_without_its_panels_and_with_the_whole_arm_in_view(monkeypatch):
    """A small window shows the arm: the viewer is asked for no side panels, and its camera looks
    at the arm from far enough that every body (and 0.1 m past it) lies inside the field of view,
    in every pose the tour takes it through."""
    import mujoco
    import mujoco.viewer
    import numpy as np

    from crslab import crs
    from crslab.live import viewer as viewer_module
    from crslab.plant.model import load_model

    class Handle:
        def __init__(self):
            self.cam = mujoco.MjvCamera()

        def lock(self):
            import contextlib
            return contextlib.nullcontext()

    asked = {}

    def launch_passive(model, data, **kwargs):
        asked.update(kwargs)
        return Handle()

    monkeypatch.setattr(mujoco.viewer, "launch_passive", launch_passive)
    monkeypatch.setattr("crslab.scopes.display.missing_display", lambda: None)
    view = viewer_module.MujocoViewer(crs.motor_to_dh(np.array([0.0, -0.42, 0.24])))
    assert view.start()
    assert asked == {"show_left_ui": False, "show_right_ui": False}
    model, data = load_model(), None
    half_fov = np.radians(model.vis.global_.fovy) / 2
    for motor_deg in ([0, -24, 14], [0, 0, 0], [0, 90, 0], [0, 0, -90], [60, 45, -30]):
        data = mujoco.MjData(model)
        data.qpos[:3] = crs.motor_to_dh(np.radians(motor_deg))
        mujoco.mj_forward(model, data)
        cam = mujoco.MjvCamera()
        viewer_module.fit_camera(cam, model, data)
        # each body's angle off the line of sight, seen from the camera, inside the half field of view
        direction = np.array([np.cos(np.radians(cam.elevation)) * np.cos(np.radians(cam.azimuth)),
                              np.cos(np.radians(cam.elevation)) * np.sin(np.radians(cam.azimuth)),
                              np.sin(np.radians(cam.elevation))])
        eye = np.asarray(cam.lookat) - cam.distance * direction
        for point in data.xpos[1:]:
            to = point - eye
            off_axis = np.arccos(np.clip(to @ direction / np.linalg.norm(to), -1, 1))
            assert off_axis < half_fov, (motor_deg, point)
        assert cam.distance < 5.0  # not a speck far away: the arm fills much of the view
