"""Step-response numbers of a recorded or simulated joint: what a control course reads off a plot.

A step starts at a sample where the reference changes and lasts until the next change; a step the
record ends in the middle of is left out. For each: the 10-90 % rise time, the overshoot past the
new reference (% of the step), the steady-state error (reference minus angle, averaged over the
step's last 100 ms) and the peak speed (largest difference between neighbouring samples over their
spacing).

>>> t = np.arange(0, 2.3, 0.005)
>>> ref = np.where((t >= 0.2) & (t < 1.2), 1.0, np.where(t >= 2.2, 1.0, 0.0))
>>> up, down = 1 - np.exp(-(t - 0.2) / 0.1), np.exp(-(t - 1.2) / 0.1)
>>> x = np.where(t < 0.2, 0.0, np.where(t < 1.2, up, down))
>>> s = steps(t, x, ref)
>>> [round(v.rise_s, 3) for v in s]       # 0.1 ln 9 = 0.2197 s, to a 5 ms sample
[0.22, 0.22]
>>> round(s[0].error_rad, 5), s[0].overshoot_pct      # exp(-9) - exp(-10) = 7.8e-5
(8e-05, 0.0)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

SETTLE_WINDOW_S = 0.1


@dataclass(frozen=True)
class Step:
    """One step of one joint: start time (s), the reference before and after, and its numbers."""

    t_s: float
    from_rad: float
    to_rad: float
    rise_s: float
    overshoot_pct: float
    error_rad: float
    peak_speed_rad_s: float

    @property
    def rising(self) -> bool:
        return self.to_rad > self.from_rad


def steps(t_s: np.ndarray, angle: np.ndarray, reference: np.ndarray, min_step: float = 0.05) -> list[Step]:
    """Every complete step of ``angle`` (rad) that ``reference`` (rad, per sample) makes of at
    least ``min_step``: from one reference change to the next (before the first change nothing is
    known of where the joint was going; after the last the record may end mid-step)."""
    bounds = list(np.nonzero(np.abs(np.diff(reference)) >= min_step)[0] + 1)
    out = []
    for start, end in zip(bounds[:-1], bounds[1:]):
        seg_t, seg_x = t_s[start:end] - t_s[start], angle[start:end]
        if len(seg_t) < 4:
            continue
        before = float(angle[start - 1])
        target = float(reference[start])
        size = target - before
        if abs(size) < min_step:
            continue
        progress = (seg_x - before) / size
        rise = _first(seg_t, progress >= 0.9) - _first(seg_t, progress >= 0.1)
        overshoot = max(0.0, float(np.max(progress)) - 1.0) * 100.0
        last = seg_t >= seg_t[-1] - SETTLE_WINDOW_S
        error = float(np.mean(target - seg_x[last]))
        speed = float(np.max(np.abs(np.diff(seg_x) / np.diff(seg_t))))
        out.append(Step(float(t_s[start]), before, target, rise, overshoot, error, speed))
    return out


def _first(t: np.ndarray, condition: np.ndarray) -> float:
    hits = np.nonzero(condition)[0]
    return float(t[hits[0]]) if len(hits) else float("nan")


@dataclass(frozen=True)
class StepSummary:
    """The means over a joint's rising (or falling) steps."""

    count: int
    rise_s: float
    overshoot_pct: float
    error_rad: float
    peak_speed_rad_s: float


def summarize(found: Sequence[Step], rising: bool) -> StepSummary:
    """Means over the rising (``rising``) or falling steps of ``found``."""
    chosen = [s for s in found if s.rising == rising]
    if not chosen:
        nan = float("nan")
        return StepSummary(0, nan, nan, nan, nan)
    return StepSummary(len(chosen), float(np.mean([s.rise_s for s in chosen])),
                       float(np.mean([s.overshoot_pct for s in chosen])),
                       float(np.mean([s.error_rad for s in chosen])),
                       float(np.mean([s.peak_speed_rad_s for s in chosen])))
