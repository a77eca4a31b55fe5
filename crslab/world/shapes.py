"""Solid shapes of a world's fixtures, as the scene builds them and the layout checks test them:
boxes turned about z, and upright cylinders (metres, the world file's frame).

>>> import math
>>> a = Box((0.0, 0.0, 0.5), (1.0, 1.0, 0.5))
>>> overlap(a, Box((2.1, 0.0, 0.5), (1.0, 0.1, 0.5))), overlap(a, Box((1.9, 0.0, 0.5), (1.0, 0.1, 0.5)))
(False, True)
>>> [overlap(a, Box((1.5, 1.5, 0.5), (1.0, 0.1, 0.5), yaw_rad=yaw)) for yaw in (math.pi / 4, -math.pi / 4)]
[True, False]
>>> overlap(a, Cylinder((1.5, 1.5), 0.7, 0.0, 1.0)), overlap(a, Cylinder((1.5, 1.5), 0.72, 0.0, 1.0))
(False, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Box:
    """A box: centre, half sizes along its own axes, turned by ``yaw_rad`` about z."""

    center: tuple[float, float, float]
    half: tuple[float, float, float]
    yaw_rad: float = 0.0
    name: str = ""

    @property
    def axes_xy(self) -> tuple[np.ndarray, np.ndarray]:
        """Its x and y axes in the world's x-y plane."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        return np.array([c, s]), np.array([-s, c])

    @property
    def z_range(self) -> tuple[float, float]:
        return self.center[2] - self.half[2], self.center[2] + self.half[2]

    def corners_xy(self) -> np.ndarray:
        """Its four corners in x-y (counterclockwise)."""
        u, v = self.axes_xy
        c, (hx, hy) = np.asarray(self.center[:2]), self.half[:2]
        return np.array([c + sx * hx * u + sy * hy * v for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))])

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Distance (m) from each point (rows, x y z) to the box; 0 inside."""
        u, v = self.axes_xy
        rel = np.asarray(points, float) - np.asarray(self.center)
        local = np.stack([rel[..., :2] @ u, rel[..., :2] @ v, rel[..., 2]], axis=-1)
        out = np.maximum(np.abs(local) - np.asarray(self.half), 0.0)
        return np.linalg.norm(out, axis=-1)

    def where(self) -> str:
        """Its extents in words (its bounding box)."""
        xy = self.corners_xy()
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        z0, z1 = self.z_range
        return f"x {lo[0]:.3f}..{hi[0]:.3f}, y {lo[1]:.3f}..{hi[1]:.3f}, z {z0:.3f}..{z1:.3f} m"


@dataclass(frozen=True)
class Cylinder:
    """An upright cylinder: its axis at ``center_xy``, ``radius``, from ``z_lo`` to ``z_hi``."""

    center_xy: tuple[float, float]
    radius: float
    z_lo: float
    z_hi: float
    name: str = ""

    @property
    def z_range(self) -> tuple[float, float]:
        return self.z_lo, self.z_hi

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Distance (m) from each point (rows, x y z) to the cylinder; 0 inside."""
        p = np.asarray(points, float)
        radial = np.maximum(
            np.hypot(p[..., 0] - self.center_xy[0], p[..., 1] - self.center_xy[1]) - self.radius, 0
        )
        axial = np.maximum(np.maximum(self.z_lo - p[..., 2], p[..., 2] - self.z_hi), 0.0)
        return np.hypot(radial, axial)

    def where(self) -> str:
        (x, y), r = self.center_xy, self.radius
        return f"x {x - r:.3f}..{x + r:.3f}, y {y - r:.3f}..{y + r:.3f}, z {self.z_lo:.3f}..{self.z_hi:.3f} m"


Shape = Box | Cylinder

_EPS = 1e-9
"""Shapes that only touch (within a nanometre) do not overlap."""


def _z_overlap(a: Shape, b: Shape) -> bool:
    (a0, a1), (b0, b1) = a.z_range, b.z_range
    return a0 < b1 - _EPS and b0 < a1 - _EPS


def _boxes_overlap_xy(a: Box, b: Box) -> bool:
    """Separating axes of two rectangles: their four edge normals."""
    ca, cb = a.corners_xy(), b.corners_xy()
    for axis in (*a.axes_xy, *b.axes_xy):
        pa, pb = ca @ axis, cb @ axis
        if pa.max() <= pb.min() + _EPS or pb.max() <= pa.min() + _EPS:
            return False
    return True


def _box_circle_overlap_xy(a: Box, c: Cylinder) -> bool:
    u, v = a.axes_xy
    rel = np.asarray(c.center_xy) - np.asarray(a.center[:2])
    local = np.array([rel @ u, rel @ v])
    outside = np.maximum(np.abs(local) - np.asarray(a.half[:2]), 0.0)
    return float(np.hypot(*outside)) < c.radius - _EPS


def overlap(a: Shape, b: Shape) -> bool:
    """Whether two shapes share a volume (touching is not overlapping)."""
    if not _z_overlap(a, b):
        return False
    if isinstance(a, Box) and isinstance(b, Box):
        return _boxes_overlap_xy(a, b)
    if isinstance(a, Cylinder) and isinstance(b, Cylinder):
        gap = math.hypot(a.center_xy[0] - b.center_xy[0], a.center_xy[1] - b.center_xy[1])
        return gap < a.radius + b.radius - _EPS
    box, cyl = (a, b) if isinstance(a, Box) else (b, a)
    return _box_circle_overlap_xy(box, cyl)  # type: ignore[arg-type]
