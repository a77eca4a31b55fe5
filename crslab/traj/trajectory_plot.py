"""Plots of a joint trajectory: position, velocity, acceleration and jerk against time, one line
per joint, waypoint arrivals marked. matplotlib with the Agg backend (no display needed)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from crslab.output_paths import with_parent
from crslab.traj.profiles import Samples

ROWS = (("q", "position (rad)"), ("qd", "velocity (rad/s)"), ("qdd", "acceleration (rad/s$^2$)"),
        ("jerk", "jerk (rad/s$^3$)"))


def plot_trajectory(t_s: np.ndarray, samples: Samples, path: str | Path, title: str = "",
                    joint_names: Sequence[str] | None = None, marks_s: Sequence[float] = ()) -> None:
    """Write a PNG (or any format matplotlib knows from the suffix) of ``samples`` over ``t_s``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n_joints = samples.q.shape[1]
    names = list(joint_names or [f"joint {j + 1}" for j in range(n_joints)])
    fig, axes = plt.subplots(len(ROWS), 1, sharex=True, figsize=(8, 9), constrained_layout=True)
    try:
        for ax, (field, label) in zip(axes, ROWS):
            values = getattr(samples, field)
            for j in range(n_joints):
                ax.plot(t_s, values[:, j], label=names[j], linewidth=1.2)
            for mark in marks_s:
                ax.axvline(mark, color="0.75", linewidth=0.8, linestyle="--", zorder=0)
            ax.set_ylabel(label)
            ax.grid(True, linewidth=0.3)
        axes[0].legend(loc="best", fontsize="small")
        axes[-1].set_xlabel("time (s)")
        if title:
            axes[0].set_title(title)
        fig.savefig(with_parent(path), dpi=110)
    finally:
        plt.close(fig)
