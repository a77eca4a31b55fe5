"""The scorecard's picture (``crslab contest -o card.png``): on the left a top view of the peg's path
over the fixtures (the hole, the obstacle's footprint, the groove's Z with its width, the egg),
on the right the scale's reading (g) against time with the contest's band, and the card's lines
as the title."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from crslab.contest.scorecard import Scorecard, column
from crslab.framework_facts import TICKS_PER_S


def draw_card(log: Mapping[str, np.ndarray], world: Any, card: Scorecard, path: Path) -> None:
    """Write the picture of ``card`` (scored from ``log`` in ``world``) to ``path`` (PNG, or any
    format matplotlib names by the suffix). Raises ``OSError`` when it cannot be written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle, Polygon, Rectangle

    t = column(log, "tick") / TICKS_PER_S
    tip = column(log, "peg_tip", 3)
    fig, (top, force) = plt.subplots(1, 2, figsize=(12, 5.6), gridspec_kw={"width_ratios": [1, 1.2]})

    hole, ob, gr, egg = (getattr(world, k, None) for k in ("hole", "obstacle", "groove", "egg"))
    if hole is not None:
        top.add_patch(Circle(hole.center_xy_m, hole.diameter_m / 2, color="tab:blue", alpha=0.5,
                             label="hole"))
    if ob is not None:
        (x, y), (sx, sy) = ob.center_xy_m, ob.size_xy_m
        top.add_patch(Rectangle((x - sx / 2, y - sy / 2), sx, sy, color="tab:red", alpha=0.35,
                                label="obstacle"))
    if gr is not None:
        c = np.asarray(gr.corners_xy_m, float)
        for a, b in zip(c[:-1], c[1:]):   # each segment as a band of the groove's width
            d = (b - a) / np.hypot(*(b - a))
            n = np.array([-d[1], d[0]]) * gr.width_m / 2
            top.add_patch(Polygon([a + n, b + n, b - n, a - n], color="tab:green", alpha=0.35))
        top.plot(c[:, 0], c[:, 1], color="tab:green", lw=0.8, label="groove")
    if egg is not None:
        top.add_patch(Circle(egg.center_xy_m, egg.diameter_m / 2, color="goldenrod", alpha=0.5, label="egg"))
    moving = np.linalg.norm(tip - tip[0], axis=1) > 0 if len(tip) else np.zeros(0, bool)
    first = int(np.argmax(moving)) if moving.any() else 0
    path_xy = tip[first:]
    sc = top.scatter(path_xy[:, 0], path_xy[:, 1], c=path_xy[:, 2], s=1.5, cmap="viridis")
    fig.colorbar(sc, ax=top, label="peg tip z [m]", shrink=0.8)
    if card.groove.left_at is not None:
        top.plot(*card.groove.left_at, "x", color="black", ms=10, label="left the groove")
    top.set_aspect("equal")
    top.autoscale_view()
    top.set_xlabel("x [m]")
    top.set_ylabel("y [m]")
    top.set_title("the peg's path, from above")
    top.legend(loc="best", fontsize=8)

    grams = column(log, "scale_g") if "scale_g" in log else np.zeros(len(t))
    lo, hi = card.rules.band_g
    force.axhspan(lo, hi, color="tab:green", alpha=0.15, label=f"band {lo:.0f}-{hi:.0f} g")
    force.plot(t, grams, color="goldenrod", lw=1.2, label="scale")
    if card.egg.broken_at_s is not None:
        force.axvline(card.egg.broken_at_s, color="tab:red", ls="--", label="egg broken")
    force.set_xlabel("t [s]")
    force.set_ylabel("scale [g]")
    force.set_title("the egg's force")
    force.legend(loc="upper left", fontsize=8)
    force.grid(alpha=0.3)

    fig.suptitle("\n".join(card.lines()), fontsize=8, family="monospace", ha="left", x=0.02)
    fig.tight_layout(rect=(0, 0, 1, 0.8))
    try:
        fig.savefig(path, dpi=110)
    finally:
        plt.close(fig)
