"""Where a recording lies on a simulated run's timeline.

A recording starts at an arbitrary point of a run, and the recorder's clock (Simulink's, on the PC)
drifts against the board's (about 200 ppm). Sample ``i`` taken at recorder time ``t_i`` shows what
the lab's last ``lab()`` call left in the PlotVars at board time

    tick(t_i) = start_tick + phase_ms + (t_i - t_0) * 1000 * (1 + drift)      (ms)

so its simulated value is the PlotVar row ``floor(tick)``; the fit uses the smooth stand-in
``interp(tick - 0.5)`` (the same on average, and differentiable in the phase and the drift).

``start_tick`` is found once by matching every recorded PlotVar against a long run; the PlotVars
that are the lab's own signals (a reference: they match the run exactly, to the recording's 1e-4
steps) then pin the phase and the drift down to the ranges where they still match sample for
sample. Those ranges bound the fit's phase and drift, so the alignment can never take up what
physics should explain.

>>> ticks = np.arange(100.0)[:, None]            # a PlotVar that counts ticks
>>> sample(ticks, np.array([0.0, 0.005, 0.010]), 20, 0.5, 0.0).ravel().tolist()
[20.0, 25.0, 30.0]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

QUANTUM = 1e-4
"""Simulink receives each PlotVar as int32(10000 * value)."""
MAX_DRIFT = 1e-3
"""The largest clock drift considered (1000 ppm; the course's setup shows about 200)."""


@dataclass(frozen=True)
class Alignment:
    """A recording's place on the simulated timeline, with the bounds of its fine terms."""

    start_tick: int
    phase_ms: float
    drift: float
    phase_bounds: tuple[float, float]
    drift_bounds: tuple[float, float]
    pinned_by: tuple[int, ...] = ()
    """The PlotVars (1..4) that are lab signals and bound the phase and drift; empty: none."""


def positions(t_s: np.ndarray, start_tick: float, phase_ms: float, drift: float) -> np.ndarray:
    """Board time (ms, as a tick position) of each recorder time ``t_s``."""
    return start_tick + phase_ms + (t_s - t_s[0]) * 1000.0 * (1.0 + drift)


def sample(per_tick: np.ndarray, t_s: np.ndarray, start_tick: float, phase_ms: float,
           drift: float) -> np.ndarray:
    """The simulated values (rows of ``per_tick``, one per tick) at the recording's samples."""
    pos = positions(t_s, start_tick, phase_ms, drift) - 0.5
    ticks = np.arange(per_tick.shape[0], dtype=float)
    return np.stack([np.interp(pos, ticks, per_tick[:, c]) for c in range(per_tick.shape[1])], axis=1)


def coarse_start(per_tick: np.ndarray, plotvars: np.ndarray, t_s: np.ndarray, earliest: int,
                 latest: int) -> int:
    """The start tick in ``[earliest, latest]`` where the run's PlotVars (``per_tick``, 4 columns)
    best match the recorded ones (``plotvars``, NaN where not recorded), at whole ticks and no drift.
    Of starts that match about equally well (a periodic lab), the earliest."""
    cols = [c for c in range(plotvars.shape[1]) if not np.all(np.isnan(plotvars[:, c]))]
    offsets = np.round((t_s - t_s[0]) * 1000.0).astype(np.int64)
    latest = min(latest, per_tick.shape[0] - 1 - int(offsets[-1]))
    if latest < earliest:
        raise ValueError("the run is too short to place the recording")
    rec = plotvars[:, cols]
    scores = np.empty(latest - earliest + 1)
    for k, s in enumerate(range(earliest, latest + 1)):
        d = per_tick[s + offsets][:, cols] - rec
        scores[k] = float(np.mean(d * d))
    best = float(scores.min())
    good = np.nonzero(scores <= best * 1.05 + 1e-12)[0]
    return earliest + int(good[0])


def fine_bounds(per_tick: np.ndarray, plotvars: np.ndarray, t_s: np.ndarray, start_tick: int,
                motor_columns: tuple[int, ...], sample_ms: float) -> Alignment:
    """The phase and drift ranges in which the recording's lab signals (PlotVars that are not motor
    angles and match the run exactly at ``start_tick``) still match sample for sample. Without such
    signals: the phase within half a recorder sample of ``start_tick``, any drift up to
    :data:`MAX_DRIFT`."""
    half = sample_ms / 2.0
    signals = []
    for c in range(plotvars.shape[1]):
        if c in motor_columns or np.all(np.isnan(plotvars[:, c])):
            continue
        if np.ptp(plotvars[:, c]) < 10 * QUANTUM:
            continue  # a constant says nothing about time
        at_start = _held(per_tick[:, c], t_s, start_tick, 0.0, 0.0)
        if np.mean(np.abs(at_start - plotvars[:, c]) > 1.5 * QUANTUM) < 0.01:
            signals.append(c)
    if not signals:
        return Alignment(start_tick, 0.0, 0.0, (-half, half), (-MAX_DRIFT, MAX_DRIFT))
    phases = np.arange(-2 * sample_ms, 2 * sample_ms + 1e-9, 0.1)
    drifts = np.arange(-MAX_DRIFT, MAX_DRIFT + 1e-12, 20e-6)
    ok = np.zeros((len(phases), len(drifts)), dtype=bool)
    rec = plotvars[:, signals]
    for i, ph in enumerate(phases):
        for k, dr in enumerate(drifts):
            sim = np.stack([_held(per_tick[:, c], t_s, start_tick, ph, dr) for c in signals], axis=1)
            ok[i, k] = not np.any(np.abs(sim - rec) > 1.5 * QUANTUM)
    if not ok.any():  # the signals never match throughout: bound as if there were none
        return Alignment(start_tick, 0.0, 0.0, (-half, half), (-MAX_DRIFT, MAX_DRIFT))
    pi, dk = np.nonzero(ok)
    pb = (float(phases[pi.min()]), float(phases[pi.max()]))
    db = (float(drifts[dk.min()]), float(drifts[dk.max()]))
    centre_phase = float(np.mean(phases[pi]))
    centre_drift = float(np.mean(drifts[dk]))
    return Alignment(start_tick, centre_phase, centre_drift, pb, db, tuple(c + 1 for c in signals))


def _held(column: np.ndarray, t_s: np.ndarray, start_tick: int, phase_ms: float,
          drift: float) -> np.ndarray:
    """Sample-and-hold: the row of the last tick at or before each sample's board time."""
    idx = np.floor(positions(t_s, start_tick, phase_ms, drift)).astype(np.int64)
    return column[np.clip(idx, 0, len(column) - 1)]
