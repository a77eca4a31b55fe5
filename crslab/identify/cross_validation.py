"""Cross-validation of a joint fit: fit on one experiment alone, predict every other.

Each experiment (a recording or a friction table) is fitted alone from the same start, with the
values it can tell (a table only friction and the motor gain); the plant found is then run
against every experiment as it stands (recordings aligned, nothing of the plant changed). A value
one experiment cannot see but another needs shows up as a poor prediction: the reason to fit them
together.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from crslab.identify.fit import FitError, FitResult, Source, TableSource, compare, fit
from crslab.plant.plant_params import PlantParams

Experiment = Source | TableSource


@dataclass(frozen=True)
class Prediction:
    """How the plant fitted on ``fitted_on`` (an experiment's name, or ``all together``) does on
    ``experiment``: for a recording the RMS of sim - real over its joints (rad), for a table the
    RMS of predicted / tabled - 1 over its numbers."""

    fitted_on: str
    experiment: str
    value: float
    is_table: bool
    own: bool
    """The experiment was (one of) those fitted on."""


def score(result: FitResult, experiment: Experiment, index: int) -> float:
    """``experiment``'s number in ``result`` (``index``: its position among the recordings or the
    tables of that result)."""
    if isinstance(experiment, TableSource):
        return result.tables[index].rms_gap()
    return float(np.sqrt(np.mean(result.rms_after[index] ** 2)))


def cross_validate(sources: Sequence[Source], tables: Sequence[TableSource], *, names: Sequence[str],
                   start: PlantParams, joint: FitResult | None = None, jobs: int = 1,
                   max_iterations: int = 30,
                   on_fit: Callable[[str], None] | None = None) -> list[Prediction]:
    """Fit on each experiment alone and predict them all; with ``joint`` (the fit on all of them)
    its row too. ``on_fit(name)`` before each fit."""
    experiments: list[Experiment] = [*sources, *tables]
    out: list[Prediction] = []
    for own in experiments:
        if on_fit is not None:
            on_fit(own.name)
        alone_sources = [own] if isinstance(own, Source) else []
        alone_tables = [own] if isinstance(own, TableSource) else []
        try:
            alone = fit(alone_sources, tables=alone_tables, names=names, start=start, jobs=jobs,
                        max_iterations=max_iterations)
        except FitError:
            continue  # nothing this experiment can tell of the values asked for
        checked = compare(list(sources), alone.plant, jobs=jobs, tables=list(tables))
        out += _row(own.name, checked, sources, tables, {own.name})
    if joint is not None:
        out += _row("all together", joint, sources, tables, {e.name for e in experiments})
    return out


def _row(label: str, result: FitResult, sources: Sequence[Source], tables: Sequence[TableSource],
         own: set[str]) -> list[Prediction]:
    row = [Prediction(label, s.name, score(result, s, i), False, s.name in own)
           for i, s in enumerate(sources)]
    row += [Prediction(label, t.name, score(result, t, i), True, t.name in own) for i, t in enumerate(tables)]
    return row


def cross_validation_lines(predictions: Sequence[Prediction]) -> list[str]:
    """A table: one line per fit (on one experiment, or all together), one column per experiment.

    >>> p = [Prediction("a.csv", "a.csv", 0.002, False, True),
    ...      Prediction("a.csv", "t.toml", 0.184, True, False)]
    >>> for line in cross_validation_lines(p): print(line)
    cross-validation (recordings: RMS sim - real, rad; tables: RMS of predicted / tabled - 1)
      fitted on \\ predicts                a.csv            t.toml
      a.csv                               0.0020 (own)     18.4 %
    """
    columns = list(dict.fromkeys(p.experiment for p in predictions))
    rows = list(dict.fromkeys(p.fitted_on for p in predictions))
    width = max(15, min(34, max(len(c) for c in columns)))
    corner = "fitted on \\ predicts"
    lines = ["cross-validation (recordings: RMS sim - real, rad; tables: RMS of predicted / tabled - 1)",
             "  " + f"{corner:34s}" + "".join(f"  {c[:width]:{width}s}" for c in columns).rstrip()]
    for r in rows:
        cells = []
        for c in columns:
            hit = [p for p in predictions if p.fitted_on == r and p.experiment == c]
            if not hit:
                cells.append(f"{'-':{width}s}")
                continue
            p = hit[0]
            text = f"{100 * p.value:.1f} %" if p.is_table else f"{p.value:.4f}"
            cells.append(f"{text + (' (own)' if p.own else ''):{width}s}")
        lines.append("  " + f"{r[:34]:34s}" + "".join(f"  {c}" for c in cells).rstrip())
    return lines
