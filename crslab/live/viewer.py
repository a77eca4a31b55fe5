"""``--viewer``: MuJoCo's own viewer on the running arm; the mouse pushes it like a hand.

The physics runs in the worker process; the viewer runs in the crslab process on its own copy of
the model. After every chunk of ticks the copy takes the arm's latest pose from the scope log,
the viewer draws it, and the force of a mouse drag (double-click a link, then Ctrl + right-drag
to pull it, Ctrl + left-drag to twist it) goes to the worker, which applies it to that link
until it changes. At real-time speed a chunk is 20 ms, so the drag acts with that delay.
Without a display, the run goes on without a viewer and one line says so. The window opens with
its panels hidden (Tab and Shift + Tab show them) and its camera fitted to the arm, so that a small
window shows the arm, not mostly panels.
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable

import numpy as np

from crslab.run.running import RunningLab
from crslab.sinks.latest_pose import LatestPose
from crslab.world import FREE_AIR, World
from crslab.world.scene import flatten_egg, load_scene, set_arm_pose

CAMERA_AZIMUTH_DEG = 135.0
CAMERA_ELEVATION_DEG = -20.0
FIT_MARGIN = 1.3
"""The arm's farthest point from the camera's target lies this many times inside the view's
half-height."""


def fit_camera(cam: object, model: object, data: object) -> None:
    """Point ``cam`` (an ``MjvCamera``) at the arm's bodies (their positions in ``data``, after
    ``mj_forward``) from far enough that every one, and the reach past it, is in view of the
    model's field of view (``vis.global.fovy``)."""
    bodies = np.asarray(data.xpos)[1:]  # type: ignore[attr-defined]  # the world body is at the origin
    center = (bodies.min(axis=0) + bodies.max(axis=0)) / 2
    reach = float(np.max(np.linalg.norm(bodies - center, axis=1))) + 0.1  # m: and the links' own length
    half_fov = np.radians(float(model.vis.global_.fovy)) / 2  # type: ignore[attr-defined]
    cam.lookat[:] = center  # type: ignore[attr-defined]
    cam.distance = FIT_MARGIN * reach / np.tan(half_fov)  # type: ignore[attr-defined]
    cam.azimuth = CAMERA_AZIMUTH_DEG  # type: ignore[attr-defined]
    cam.elevation = CAMERA_ELEVATION_DEG  # type: ignore[attr-defined]


class MujocoViewer(LatestPose):
    """MuJoCo's passive viewer following a run: a sink (what :class:`LatestPose` keeps of the scope
    rows, drawn between chunks) and a live control (the mouse's push, :meth:`serve`); call
    :meth:`start` once the worker exists."""

    def __init__(self, rest_dh_rad: np.ndarray, on_status: Callable[[str], None] | None = None,
                 world: World = FREE_AIR) -> None:
        super().__init__()
        self.on_status = on_status or (lambda line: print(line, file=sys.stderr))
        self.world = world
        """What the run's arm can touch: its scene is the one shown (the fixtures with the arm)."""
        self.rest_dh_rad = np.asarray(rest_dh_rad, dtype=float)
        self.handle = None
        self._sent = None
        self._threads: list[threading.Thread] = []

    def start(self) -> bool:
        """Open the window; False (after one line on why) when it cannot open."""
        before = set(threading.enumerate())
        from crslab.scopes.display import missing_display

        why = missing_display()
        if why:
            self.on_status(f"--viewer: {why}; running without MuJoCo's viewer")
            return False
        try:
            import mujoco
            import mujoco.viewer

            self.model = load_scene(self.world)
            self.data = mujoco.MjData(self.model)
            set_arm_pose(self.model, self.data, self.rest_dh_rad)
            self._forward = mujoco.mj_forward
            self._forward(self.model, self.data)
            self.handle = mujoco.viewer.launch_passive(self.model, self.data, show_left_ui=False,
                                                       show_right_ui=False)
            with self.handle.lock():
                fit_camera(self.handle.cam, self.model, self.data)
        except Exception as exc:  # noqa: BLE001 - no OpenGL, no mjpython on macOS...: one line
            self.on_status(f"--viewer: MuJoCo's viewer did not open ({str(exc).splitlines()[0]}); "
                           "running without it")
            self.handle = None
            return False
        self._sent = np.zeros_like(self.data.xfrc_applied)
        self._threads = [t for t in threading.enumerate() if t not in before]  # the window's thread
        return True

    def serve(self, lab: RunningLab) -> None:
        """Show the latest pose and pass the mouse's push to the running lab (between chunks)."""
        if self.handle is None or not self.handle.is_running():
            return
        with self.handle.lock():
            if self.qpos_dh_rad is not None:
                set_arm_pose(self.model, self.data, self.qpos_dh_rad)
            if self.egg_broken:
                flatten_egg(self.model)
            self._forward(self.model, self.data)
        self.handle.sync()  # draws, and turns a mouse drag into data.xfrc_applied
        push = self.data.xfrc_applied.copy()
        if not np.array_equal(push, self._sent):
            lab.push(push)
            self._sent = push

    def close(self) -> None:
        """Close the window and wait for its thread (exiting while it tears down would crash)."""
        if self.handle is not None:
            self.handle.close()
            self.handle = None
            for thread in self._threads:
                thread.join(5.0)
