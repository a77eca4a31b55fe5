"""What a sweep measures in one run, from its scope log (one row per tick) and the board's
counters, in the process that ran it (the lab's worker only sends the columns).

Signals are taken from the tick the startup gate opens (the lab's first call) to the end:

- ``safety_trips``: times the arm left the safety envelope (the flag's rises);
- ``motor_board_cutouts``: times the motor board cut every output;
- ``trips_before_lab``: how many of those trips and cut-outs came by the lab's first call, on angles
  its torques never moved (the arm and its setup, not the lab: a payload the hold controller
  cannot hold, say);
- ``clamp_share``: share of the lab's ticks where it commanded a joint at or beyond the +-5 clamp;
- ``plotvarK_rms`` / ``plotvarK_maxabs``: RMS and largest magnitude of ``Simulink_PlotVarK``;
- ``plotvarK_err_rms`` / ``plotvarK_err_maxabs`` (K = 1..3): the same of PlotVarK - PlotVar4, the
  course's usual layout of actual (1-3) against desired (4);
- ``thetaJmotor_final_rad``: the motor angles the encoders read at the last tick;
- ``over_budget``: lab() calls that cost more than the budget (``--budget``).

>>> log = {"tick": np.arange(4).reshape(-1, 1), "safety": np.array([[0], [1], [0], [1]]),
...        "tau_lab": np.array([[0, 0, 0], [5, 0, 0], [0, -6, 0], [1, 1, 1]], float),
...        "plot": np.array([[1, 0, 0, 1], [3, 0, 0, 1], [1, 0, 0, 1], [3, 0, 0, 1]], float),
...        "enc_rad": np.zeros((4, 3))}
>>> from crslab.worker.run_stats import RunStats
>>> stats = RunStats(motor_board_events=((2, 1, True), (9, 1, False)))
>>> m = run_metrics(log, stats, startup_ticks=0)
>>> m["safety_trips"], m["motor_board_cutouts"], m["clamp_share"], m["plotvar1_rms"], m["plotvar1_err_maxabs"]
(2, 1, 0.5, 2.23606797749979, 2.0)
>>> run_metrics(log, stats, startup_ticks=3)["trips_before_lab"]
3
"""

from __future__ import annotations

import math

import numpy as np

from crslab.framework_facts import CLAMP_UNITS
from crslab.worker.run_stats import RunStats

PLOT_VARS = 4
ACTUAL_VS_DESIRED = (1, 2, 3)
"""PlotVars compared with PlotVar4."""
METRIC_NAMES: tuple[str, ...] = (
    "safety_trips", "motor_board_cutouts", "trips_before_lab", "clamp_share",
    *(f"plotvar{k}_{s}" for k in range(1, PLOT_VARS + 1) for s in ("rms", "maxabs")),
    *(f"plotvar{k}_err_{s}" for k in ACTUAL_VS_DESIRED for s in ("rms", "maxabs")),
    *(f"theta{j}motor_final_rad" for j in (1, 2, 3)),
    "over_budget",
)
"""Every metric, in table order."""
INTEGER_METRICS = frozenset({"safety_trips", "motor_board_cutouts", "trips_before_lab", "over_budget"})


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(x)))) if x.size else math.nan


def _maxabs(x: np.ndarray) -> float:
    return float(np.max(np.abs(x))) if x.size else math.nan


def run_metrics(log: dict[str, np.ndarray] | None, stats: RunStats, *,
                startup_ticks: int) -> dict[str, float]:
    """Every metric of :data:`METRIC_NAMES` for one run (NaN where the run gave no signal: it
    ended before the lab's first call)."""
    out: dict[str, float] = {name: math.nan for name in METRIC_NAMES}
    cutouts = [event[0] for event in stats.motor_board_events if event[2]]
    out["motor_board_cutouts"] = len(cutouts)
    out["over_budget"] = stats.over_budget
    early_cutouts = sum(1 for tick in cutouts if tick <= startup_ticks)
    if log is None or len(log["tick"]) == 0:
        out["safety_trips"] = 0
        out["trips_before_lab"] = early_cutouts
        return out
    safety = log["safety"].ravel().astype(np.int64)
    rises = np.diff(safety, prepend=0) > 0
    out["safety_trips"] = int(np.count_nonzero(rises))
    early_trips = int(np.count_nonzero(rises & (log["tick"].ravel() <= startup_ticks)))
    out["trips_before_lab"] = early_trips + early_cutouts
    enc = log["enc_rad"][-1]
    for j in range(3):
        out[f"theta{j + 1}motor_final_rad"] = float(enc[j])
    lab = log["tick"].ravel() >= startup_ticks
    if not lab.any():
        return out
    tau = log["tau_lab"][lab]
    out["clamp_share"] = float(np.mean(np.any(np.abs(tau) >= CLAMP_UNITS, axis=1)))
    plot = log["plot"][lab]
    for k in range(PLOT_VARS):
        out[f"plotvar{k + 1}_rms"] = _rms(plot[:, k])
        out[f"plotvar{k + 1}_maxabs"] = _maxabs(plot[:, k])
    for k in ACTUAL_VS_DESIRED:
        err = plot[:, k - 1] - plot[:, PLOT_VARS - 1]
        out[f"plotvar{k}_err_rms"] = _rms(err)
        out[f"plotvar{k}_err_maxabs"] = _maxabs(err)
    return out
