"""What a window drawing the running arm needs from a run: the arm's latest pose, and whether the
egg broke (``--viewer``'s :class:`crslab.live.viewer.MujocoViewer` is one; it draws between chunks
of ticks what this sink kept from the last chunk's scope rows).

>>> import numpy as np
>>> pose = LatestPose()
>>> rows = {"qpos_dh_rad": np.array([[0.0, 0.1, 0.2], [0.0, 0.3, 0.4]]), "egg_broken": np.array([[0], [1]])}
>>> pose.on_log(rows)
>>> pose.qpos_dh_rad.tolist(), pose.egg_broken
([0.0, 0.3, 0.4], True)
>>> pose.on_log({"qpos_dh_rad": np.zeros((0, 3)), "egg_broken": np.zeros((0, 1))})  # an empty chunk
>>> pose.qpos_dh_rad.tolist(), pose.egg_broken
([0.0, 0.3, 0.4], True)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from crslab.sinks.sink import Sink

if TYPE_CHECKING:
    import numpy as np


class LatestPose(Sink):
    """Keeps the arm's pose of the last scope row (DH angles, rad) and whether the egg has broken
    (it stays broken: the last row of a world with an egg says so from then on)."""

    def __init__(self) -> None:
        self.qpos_dh_rad: np.ndarray | None = None
        """The last row's DH angles (None: no row yet)."""
        self.egg_broken = False

    def on_log(self, columns: dict[str, np.ndarray]) -> None:
        if len(columns["qpos_dh_rad"]):
            self.qpos_dh_rad = columns["qpos_dh_rad"][-1]
        if "egg_broken" in columns and len(columns["egg_broken"]) and columns["egg_broken"][-1, 0] > 0:
            self.egg_broken = True
