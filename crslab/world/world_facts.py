"""The world's facts for Python, read through cffi from the C that the board's world is built from
(``csrc/plant/world_facts.h``, ``csrc/plant/world.h``; called through :mod:`crslab._bindings`): the world
row's columns, the fixtures' order, how the egg breaks and lies, the contest's rules. Nothing here
is written twice: this module only names what C says.

>>> list(WORLD_COLUMNS)[:4], WORLD_COLUMNS["peg_tip"], WORLD_ROW_WIDTH
(['peg_tip', 'peg_depth', 'egg_force', 'egg_force_xyz'], 3, 23)
>>> FIXTURES[:3], EGG_FLAT_SHARE, EGG_BROKEN_BY[2]
(('table', 'hole', 'obstacle'), 0.2, 'a side hit')
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from crslab import _bindings as core
from crslab._bindings import constants as C


@dataclass(frozen=True)
class WorldColumn:
    """One quantity of the world's row (``crs_world_column``): its scope-log name, unit, what it is,
    its offset and width (3: x, y, z)."""

    name: str
    unit: str
    what: str
    offset: int
    width: int


def _columns() -> tuple[WorldColumn, ...]:
    return tuple(WorldColumn(*column) for column in core.world_columns())


COLUMNS: tuple[WorldColumn, ...] = _columns()
"""The world row's quantities, in order (docs/worlds.md's table)."""
WORLD_COLUMNS: dict[str, int] = {c.name: c.width for c in COLUMNS}
"""The scope log's world columns by name: their widths, in row order."""
WORLD_ROW_WIDTH: int = C.CRS_WORLD_ROW
"""Values in one world row."""

FIXTURES: tuple[str, ...] = core.world_fixture_names()
"""The bodies with a force sensor, in the scene's sensor order after the peg tip (each
``NAME_force`` at ``NAME_site``)."""

OBSTACLE_BODIES: dict[str, str] = {part: FIXTURES[index] for part, index in (
    ("peg", C.CRS_FIXTURE_OBSTACLE), ("forearm", C.CRS_FIXTURE_OBSTACLE_FOREARM),
    ("upper_arm", C.CRS_FIXTURE_OBSTACLE_UPPER_ARM))}
"""The obstacle's three bodies by the part of the arm each is touched by (``peg``, ``forearm``,
``upper_arm``)."""

EGG_FLAT_SHARE: float = C.CRS_EGG_FLAT_SHARE
"""A broken egg keeps this share of its height, lying on its scale."""
EGG_FALL_M_S: float = C.CRS_EGG_FALL_M_S
"""A tip that came down onto the egg faster than this (m/s) broke it in a fall."""
EGG_BROKEN_BY: dict[int, str] = {
    code: core.egg_broken_by_name(code)
    for code in (C.CRS_EGG_BROKEN_BY_PRESS, C.CRS_EGG_BROKEN_BY_SIDE, C.CRS_EGG_BROKEN_BY_FALL)
}
"""What broke the egg, by the row's ``egg_broken_by`` code (0, whole, is not in it)."""

SCALE_GRAVITY_M_S2: float = C.CRS_SCALE_GRAVITY_M_S2
"""What a scale divides a force by to show grams (m/s^2): scales are calibrated to standard gravity."""
TOUCH_N: float = C.CRS_CONTEST_TOUCH_N
"""A contact force above this (N) is a touch."""
CONTEST_BAND_G: tuple[float, float] = (C.CRS_CONTEST_BAND_LOW_G, C.CRS_CONTEST_BAND_HIGH_G)
CONTEST_HOLD_S: float = C.CRS_CONTEST_HOLD_S
CONTEST_HOLD_TOLERANCE_S: float = C.CRS_CONTEST_HOLD_TOLERANCE_S
CONTEST_PEG_MIN_DEPTH_M: float = C.CRS_CONTEST_PEG_MIN_DEPTH_M
CONTEST_PEG_HOLD_S: float = C.CRS_CONTEST_PEG_HOLD_S
CONTEST_GROOVE_MIN_SHARE: float = C.CRS_CONTEST_GROOVE_MIN_SHARE
CONTEST_OBSTACLE_AROUND: bool = bool(C.CRS_CONTEST_OBSTACLE_AROUND)
"""The contest's rules by default (a world file's ``[contest]`` table overrides each)."""


def flatten_egg_geom(size_m: np.ndarray, pos_m: np.ndarray) -> None:
    """Lay an egg geom flat onto its scale in place, as the board does when it breaks (``size_m``,
    ``pos_m``: its half sizes and centre, float64 arrays of 3): C's ``crs_egg_flatten``.

    >>> size, pos = np.array([0.022, 0.022, 0.0285]), np.array([0.2, 0.2, 0.269])
    >>> flatten_egg_geom(size, pos); round(float(size[2]), 5), round(float(pos[2] - size[2]), 4)
    (0.0057, 0.2405)
    """
    for a in (size_m, pos_m):
        if a.dtype != np.float64 or a.shape != (3,) or not a.flags.c_contiguous:
            raise ValueError("an egg geom's size and position: 3 contiguous float64 values each")
    core.egg_flatten(size_m, pos_m)


def peg_depths(
    hole_xy_m: tuple[float, float], top_z_m: float, radius_m: float, tips_m: np.ndarray
) -> np.ndarray:
    """How deep each tip (rows of x, y, z, m) is in a hole: C's ``crs_peg_depth``, the board's own
    (below the hole's top while within its radius of the axis; else 0).

    >>> peg_depths((0.034, 0.35), 0.17, 0.007, np.array([[0.034, 0.35, 0.12], [0.1, 0.35, 0.12]])).round(6)
    array([0.05, 0.  ])
    """
    tips = np.ascontiguousarray(tips_m, dtype=np.float64).reshape(-1, 3)
    out = np.zeros(len(tips))
    hole = np.array(hole_xy_m, dtype=np.float64)
    core.peg_depths(hole, top_z_m, radius_m, tips, out, len(tips))
    return out


def groove_nearest(corners_xy_m: object, points_m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The nearest point of the groove's centre line (4 corners) to each point (rows of x, y[, z]):
    its segment (0 to 2), the distance to it (m) and how far along the line from the entrance it
    is (m). C's ``crs_groove_nearest``, the board's own.

    >>> seg, off, along = groove_nearest([(0, 0), (0.03, -0.04), (0, -0.04), (0.03, -0.08)],
    ...                                  np.array([[0.023, -0.014], [0.01, -0.041]]))
    >>> seg.tolist(), off.round(6).tolist(), along.round(6).tolist()
    ([0, 1], [0.01, 0.001], [0.025, 0.07])
    """
    pts = np.ascontiguousarray(points_m, dtype=np.float64)
    pts = pts.reshape(len(pts), -1)
    corners = np.ascontiguousarray(corners_xy_m, dtype=np.float64).reshape(8)
    n = len(pts)
    segment, offset, along = np.zeros(n, np.int32), np.zeros(n), np.zeros(n)
    core.groove_nearest(corners, pts, n, pts.shape[1], segment, offset, along)
    return segment, offset, along


def split_world_row(row: object) -> dict:
    """The world's row (:data:`WORLD_ROW_WIDTH` values, or rows of them) split into named columns
    (:data:`WORLD_COLUMNS`, C's order).

    >>> split_world_row(np.arange(23.0))["scale_g"], split_world_row(np.zeros((2, 23)))["peg_tip"].shape
    (array([8.]), (2, 3))
    """
    a = np.asarray(row, dtype=float)
    flat = a.ndim == 1
    a = a.reshape(-1, WORLD_ROW_WIDTH)
    out, i = {}, 0
    for name, width in WORLD_COLUMNS.items():
        out[name] = a[0, i:i + width] if flat else a[:, i:i + width].copy()
        i += width
    return out
