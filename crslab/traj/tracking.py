"""Tracking a waypoint trajectory on the simulated arm (``crslab sim --waypoints pts.csv``).

crslab plans the waypoint file (IK, limits, durations: :mod:`crslab.traj.waypoints`), writes the
joint waypoints, durations, profile and speed limit into the tracking lab's watched variables
before the first tick, and the lab plans the same moves in C inside ``lab()`` and follows them.
Afterwards the measured motor angles are compared with the plan, tick by tick.

The lab's timing comes from the lab itself (its ``approach_s`` and ``hold_s`` variables): the
waypoint path starts ``approach_s + hold_s`` after the first ``lab()`` call.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from crslab import resources
from crslab.framework_facts import CLAMP_UNITS, TICKS_PER_S
from crslab.output_paths import with_parent
from crslab.run.running import RunningLab
from crslab.traj.profiles import PROFILES
from crslab.traj.waypoints import WaypointPlan

TRACKING_LAB = resources.path("csrc", "labs", "lab2_tracking.c")
REQUIRED = ("n_waypoints", "wp_profile", "wp_vmax_rad_s", "wp_motor_rad", "wp_duration_s", "approach_s",
            "hold_s")


class TrackingError(ValueError):
    """The lab cannot follow this waypoint file (it lacks the variables, or has too little room)."""


def write_plan(sim: RunningLab, plan: WaypointPlan, vmax_rad_s: float | None) -> float:
    """Write ``plan`` into the running lab's watched variables (before the first tick).

    Returns the time (s, after the first lab() call) at which the lab starts the waypoint path.
    """
    watched = {v.name: v for v in sim.config.build.watched}
    missing = [n for n in REQUIRED if n not in watched]
    if missing:
        raise TrackingError(f"{sim.config.build.source.name} cannot follow waypoints: it does not watch "
                            f"{', '.join(missing)} (see {TRACKING_LAB.name})")
    q = plan.q_rad
    room = watched["wp_duration_s"].length or 0
    if q.shape[0] > min(room + 1, (watched["wp_motor_rad"].length or 0) // 3):
        raise TrackingError(f"{plan.waypoints.name}: {q.shape[0]} waypoints, but the lab has room for "
                            f"{min(room + 1, (watched['wp_motor_rad'].length or 0) // 3)}")
    sim.set("n_waypoints", q.shape[0])
    sim.set("wp_profile", PROFILES[plan.trajectory.profile])
    sim.set("wp_vmax_rad_s", vmax_rad_s or 0.0)
    for i, row in enumerate(q):
        for j, value in enumerate(row):
            sim.set("wp_motor_rad", float(value), index=3 * i + j)
    for i, d in enumerate(plan.trajectory.duration_s):
        sim.set("wp_duration_s", float(d), index=i)
    return float(sim.get("approach_s")) + float(sim.get("hold_s"))


@dataclass(frozen=True)
class TrackingReport:
    """How well the arm followed the path: per joint, in motor angles (rad) and seconds."""

    max_error_rad: np.ndarray
    rms_error_rad: np.ndarray
    saturated_s: np.ndarray
    t_s: np.ndarray
    desired_rad: np.ndarray
    actual_rad: np.ndarray

    def lines(self) -> list[str]:
        """The report as text, one line per joint."""
        return [f"joint {j + 1}: max error {np.degrees(self.max_error_rad[j]):.3f} deg, "
                f"RMS {np.degrees(self.rms_error_rad[j]):.3f} deg, "
                f"torque saturated {self.saturated_s[j]:.3f} s" for j in range(3)]


def tracking_report(log: dict[str, np.ndarray], plan: WaypointPlan, path_start_tick: int) -> TrackingReport:
    """Compare the measured motor angles with the plan over the path (and its last tick).

    ``log`` holds the run's scope columns (one row per tick); saturation counts every tick at
    which the lab asked for more than the +-5 clamp allows.
    """
    ticks = log["tick"][:, 0]
    end_tick = path_start_tick + int(round(plan.trajectory.end_s * TICKS_PER_S))
    rows = (ticks >= path_start_tick) & (ticks <= end_tick)
    if not rows.any():
        raise TrackingError("the run ended before the waypoint path began: give a longer --duration")
    t = (ticks[rows] - path_start_tick) / TICKS_PER_S
    desired = plan.trajectory.evaluate(t).q
    actual = log["enc_rad"][rows]
    err = desired - actual
    saturated = (np.abs(log["tau_lab"]) > CLAMP_UNITS).sum(axis=0) / TICKS_PER_S
    return TrackingReport(np.abs(err).max(axis=0), np.sqrt((err ** 2).mean(axis=0)), saturated,
                          t, desired, actual)


def plot_tracking(report: TrackingReport, path: Path) -> None:
    """Desired against actual motor angle, one panel per joint, as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
    for j, ax in enumerate(axes):
        ax.plot(report.t_s, np.degrees(report.desired_rad[:, j]), label="desired")
        ax.plot(report.t_s, np.degrees(report.actual_rad[:, j]), "--", label="actual")
        ax.set_ylabel(f"motor {j + 1} (deg)")
        ax.grid(True, alpha=0.3)
    axes[0].legend(loc="best")
    axes[0].set_title("Tracking: desired vs actual motor angles")
    axes[-1].set_xlabel("time along the path (s)")
    fig.tight_layout()
    fig.savefig(with_parent(path), dpi=110)
    plt.close(fig)
