"""The scope log's world row (``crs_world.row``, csrc/plant/world.h ``CRS_WORLD_ROW_*``): one value
after another, split here into the quantities a scope, a CSV and the contest's card read by name.
The board writes the scope log's rows into the shared block (``crs_scope_log``, csrc/board/board.h),
where the crslab process takes them (crslab/run/shared_block.py); the board's own reading of the
world's last row is :meth:`crslab.worker.board.Board.world_values`.

>>> split_world_row(np.arange(11.0))["scale_g"], split_world_row(np.zeros((2, 11)))["peg_tip"].shape
(array([4.]), (2, 3))
"""

from __future__ import annotations

import numpy as np

WORLD_COLUMNS = {  # the C log's "world" row (csrc/plant/world.h CRS_WORLD_ROW_*), split by name: width
    "peg_tip": 3, "egg_force": 1, "scale_g": 1, "egg_broken": 1, "hole_force": 1, "obstacle_force": 1,
    "groove_side_force": 1, "groove_force": 1, "table_force": 1,
}
"""The scope log's world columns (docs/worlds.md), in a run whose world has fixtures."""


def split_world_row(row: object) -> dict:
    """The world's row (``CRS_WORLD_ROW`` values, or rows of them) split into named columns."""
    a = np.asarray(row, dtype=float)
    flat = a.ndim == 1
    a = a.reshape(-1, sum(WORLD_COLUMNS.values()))
    out, i = {}, 0
    for name, width in WORLD_COLUMNS.items():
        out[name] = a[0, i:i + width] if flat else a[:, i:i + width].copy()
        i += width
    return out
