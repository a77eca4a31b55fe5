"""Workspaces: sample where a robot's end effector can go, and draw it (seeds 001 and 002).

The *reachable* workspace is sampled by forward kinematics of joint angles drawn uniformly inside
the limits (a full turn for an unlimited joint). The *dextrous* workspace of the planar 3R arm
(the points reachable with every heading phi) is found on a grid with the closed-form IK.

>>> from crslab import robots
>>> points = reachable_points(robots.load("rrr"), 1000)
>>> points.shape, bool(np.all(np.linalg.norm(points, axis=1) <= 20 + 1e-9))
((1000, 3), True)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from crslab.closed_ik import OK
from crslab.output_paths import with_parent
from crslab.robots import Robot


def random_configurations(robot: Robot, n: int, seed: int = 0) -> np.ndarray:
    """``n`` joint configurations (rad) drawn uniformly inside the limits, ``(n, joints)``."""
    c = robot.chain
    lo = np.where(np.isfinite(c.lower), c.lower, -np.pi)
    hi = np.where(np.isfinite(c.upper), c.upper, np.pi)
    return np.random.default_rng(seed).uniform(lo, hi, size=(n, c.n_joints))


def reachable_points(robot: Robot, n: int = 20000, seed: int = 0) -> np.ndarray:
    """End-effector positions of ``n`` random in-limit configurations, ``(n, 3)``."""
    return robot.fk(random_configurations(robot, n, seed))[:, :3, 3]


def dextrous_grid(robot: Robot, cells: int = 121, headings: int = 72) -> tuple[np.ndarray, np.ndarray]:
    """Grid points ``(m, 2)`` of a planar 3R arm and a mask of those reachable at every heading.

    A point counts as dextrous when the closed-form IK has an in-limit solution for each of
    ``headings`` evenly spaced phi in [0, 2 pi).
    """
    if robot.closed_form != "planar_3r":
        raise ValueError(f"the dextrous workspace is defined here for the planar 3R arm, not {robot.name!r}")
    reach = float(np.sum(robot.chain.a))
    axis = np.linspace(-reach, reach, cells)
    xy = np.stack(np.meshgrid(axis, axis, indexing="xy"), -1).reshape(-1, 2)
    phi = np.linspace(0.0, 2 * np.pi, headings, endpoint=False)
    targets = np.concatenate([np.repeat(xy[:, None, :], headings, 1),
                              np.broadcast_to(phi[None, :, None], (len(xy), headings, 1))], -1)
    solutions = robot.closed_ik(targets)
    reachable_at_heading = np.any(solutions.status == OK, axis=-1)
    return xy, np.all(reachable_at_heading, axis=-1)


def plot(robot: Robot, path: str | Path, n: int = 20000, dextrous: bool = False, seed: int = 0) -> Path:
    """Write a PNG of the reachable workspace (and, for the planar 3R arm, the dextrous one)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    points = reachable_points(robot, n, seed)
    unit = robot.length_unit
    if robot.planar:
        fig, ax = plt.subplots(figsize=(6.5, 6))
        ax.scatter(points[:, 0], points[:, 1], s=1, alpha=0.25, color="tab:blue", label="reachable")
        if dextrous:
            xy, mask = dextrous_grid(robot)
            ax.scatter(xy[mask, 0], xy[mask, 1], s=3, color="tab:red", label="dextrous (every heading)")
        ax.set(xlabel=f"x ({unit})", ylabel=f"y ({unit})", aspect="equal")
        ax.legend(loc="upper right", markerscale=6)
    else:
        if dextrous:
            raise ValueError("--dextrous is available for the planar 3R arm only")
        fig = plt.figure(figsize=(15, 4.8))
        ax3 = fig.add_subplot(1, 3, 1, projection="3d")
        ax3.scatter(points[:, 0], points[:, 1], points[:, 2], s=1, alpha=0.5, c=points[:, 2], cmap="viridis")
        ax3.set(xlabel=f"x ({unit})", ylabel=f"y ({unit})", zlabel=f"z ({unit})", title="3-D view")
        ax3.set_box_aspect(None, zoom=0.85)
        for k, (i, j, name) in enumerate(((0, 1, "top view"), (0, 2, "side view"))):
            ax = fig.add_subplot(1, 3, k + 2)
            ax.scatter(points[:, i], points[:, j], s=0.5, alpha=0.2)
            ax.set(xlabel=f"{'xyz'[i]} ({unit})", ylabel=f"{'xyz'[j]} ({unit})", title=name, aspect="equal")
    fig.suptitle(f"{robot.name}: reachable workspace ({n} random in-limit configurations)", fontsize=10)
    fig.tight_layout()
    out = Path(path)
    fig.savefig(with_parent(out), dpi=110)
    plt.close(fig)
    return out
