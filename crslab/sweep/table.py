"""A sweep's table: rows kept as they finish (a journal that survives Ctrl-C and crashes), the
final file sorted by sample (CSV or Parquet, by the extension), the one-screen summary and the
plot of each metric against each varied quantity.

Values are written exactly: a float as the shortest text that reads back to the same number, so
the same runs give the same file byte for byte, whichever executor ran them.

>>> cell(0.1), cell(3), cell(float("nan")), cell(True)
('0.1', '3', 'nan', 'True')
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

import numpy as np

from crslab.output_paths import with_parent
from crslab.sweep.run_metrics import INTEGER_METRICS, METRIC_NAMES
from crslab.sweep.sample_job import Row
from crslab.sweep.variations import Vary, describe

if TYPE_CHECKING:
    from matplotlib.figure import Figure

FORMATS = (".csv", ".parquet")
JOURNAL_SUFFIX = ".partial.csv"


def cell(value: object) -> str:
    """One CSV cell: floats exactly (``repr``), everything else as text."""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def journal_path(output: Path) -> Path:
    """Where rows go as they finish: ``results.csv.partial.csv`` beside the output."""
    return output.with_name(output.name + JOURNAL_SUFFIX)


class Journal:
    """Rows appended as they finish, flushed at once: if crslab is killed, every finished row is
    in this CSV (unsorted)."""

    def __init__(self, path: Path, columns: Sequence[str]) -> None:
        self.path = path
        self.columns = list(columns)
        self._file: TextIO = path.open("w", newline="")
        self._writer = csv.writer(self._file)
        self._writer.writerow(self.columns)
        self._file.flush()

    def add(self, row: Row) -> None:
        self._writer.writerow([cell(row[c]) for c in self.columns])
        self._file.flush()

    def close(self) -> None:
        self._file.close()


def write_table(path: Path, columns: Sequence[str], rows: Sequence[Row]) -> None:
    """Write ``rows`` sorted by sample to ``path`` (CSV or Parquet by its extension), through a
    temporary file renamed into place, so the file is never half written."""
    ordered = sorted(rows, key=lambda r: int(r["sample"]))  # type: ignore[call-overload]
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        if path.suffix.lower() == ".parquet":
            _write_parquet(tmp, columns, ordered)
        else:
            with tmp.open("w", newline="") as f:
                w = csv.writer(f)
                w.writerow(columns)
                for row in ordered:
                    w.writerow([cell(row[c]) for c in columns])
        tmp.replace(path)
    finally:
        tmp.unlink(missing_ok=True)


def _write_parquet(path: Path, columns: Sequence[str], rows: Sequence[Row]) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    fields = []
    for c in columns:
        if c == "sample":
            t = pa.int64()
        elif c in ("status", "message"):
            t = pa.string()
        elif c in ("passed", "golden_match"):
            t = pa.bool_()
        else:
            t = pa.float64()
        fields.append(pa.field(c, t))
    schema = pa.schema(fields)
    data = {
        f.name: [float(r[f.name]) if f.type == pa.float64() else r[f.name] for r in rows]  # type: ignore
        for f in fields
    }
    pq.write_table(pa.table(data, schema=schema), path)


def read_table(path: Path) -> list[dict[str, object]]:
    """A written table's rows as dicts (CSV cells as text, Parquet values as Python values)."""
    if path.suffix.lower() == ".parquet":
        import pyarrow.parquet as pq

        return pq.read_table(path).to_pylist()
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def _badness(row: Row) -> tuple:
    """Sort key: the worst sample first (failed, not ok, trips, cut-outs, largest error)."""
    errors = [float(row[f"plotvar{k}_err_rms"]) for k in (1, 2, 3)]  # type: ignore[arg-type]
    error = max((e for e in errors if not math.isnan(e)), default=0.0)
    clamp = float(row["clamp_share"])  # type: ignore[arg-type]
    return (
        bool(row["passed"]),
        row["status"] == "ok",
        -_num(row["safety_trips"]),
        -_num(row["motor_board_cutouts"]),
        -error,
        -(0.0 if math.isnan(clamp) else clamp),
        row["sample"],
    )


def _num(value: object) -> float:
    x = float(value)  # type: ignore[arg-type]
    return 0.0 if math.isnan(x) else x


def shown_metrics(rows: Sequence[Row]) -> list[str]:
    """The metrics worth showing: those some run measured as non-zero."""
    out = []
    for name in METRIC_NAMES:
        values = np.array([float(r[name]) for r in rows], dtype=float)  # type: ignore[arg-type]
        finite = values[np.isfinite(values)]
        if finite.size and np.any(finite != 0):
            out.append(name)
    return out


def _fmt(x: float, integer: bool = False) -> str:
    if math.isnan(x):
        return "-"
    return f"{x:.0f}" if integer else f"{x:.4g}"


def summary(rows: Sequence[Row], varies: Sequence[Vary], *, total: int, golden: bool) -> list[str]:
    """The one-screen summary: statuses, pass rate, what failed, each metric's range, the worst
    sample and its values."""
    n = len(rows)
    lines = []
    if n < total:
        lines.append(f"{n} of {total} runs finished (interrupted)")
    statuses: dict[str, int] = {}
    for r in rows:
        statuses[str(r["status"])] = statuses.get(str(r["status"]), 0) + 1
    lines.append(
        "status: " + ", ".join(f"{k} {v}" for k, v in sorted(statuses.items(), key=lambda kv: -kv[1]))
    )
    passed = sum(bool(r["passed"]) for r in rows)
    rate = f" ({100.0 * passed / n:.1f} %)" if n else ""
    why = []
    for label, test in (
        ("left the safety envelope", lambda r: _num(r["safety_trips"]) > 0),
        ("motor board cut out", lambda r: _num(r["motor_board_cutouts"]) > 0),
        (
            "transcript differs from the golden file",
            lambda r: golden and r["status"] == "ok" and not r["golden_match"],
        ),
    ):
        k = sum(1 for r in rows if test(r))
        if k:
            why.append(f"{label}: {k}")
    lines.append(f"passed: {passed} of {n}{rate}" + (f"; {', '.join(why)}" if why else ""))
    early = sum(1 for r in rows if _num(r["trips_before_lab"]) > 0)
    if early:
        lines.append(f"note: in {early} of {n} runs the arm left the safety envelope or the motor board cut "
                     "out by lab()'s first call, before its torques moved the arm: the arm and its setup, "
                     "not the lab (the hold controller alone could not hold it with those variations)")
    metrics = shown_metrics(rows)
    if metrics:
        width = max(len(m) for m in metrics)
        lines.append(f"{'metric':<{width}}  {'min':>10}  {'median':>10}  {'max':>10}")
        for m in metrics:
            v = np.array([float(r[m]) for r in rows], dtype=float)  # type: ignore[arg-type]
            v = v[np.isfinite(v)]
            integer = m in INTEGER_METRICS
            lines.append(
                f"{m:<{width}}  {_fmt(float(v.min()), integer):>10}  "
                f"{_fmt(float(np.median(v))):>10}  {_fmt(float(v.max()), integer):>10}"
            )
    if rows:
        worst = min(rows, key=_badness)
        values = [float(worst[v.name]) for v in varies]  # type: ignore[arg-type]
        detail = f"; {worst['message']}" if worst["message"] else ""
        state = "passed" if worst["passed"] else "failed"
        lines.append(
            f"worst: sample {worst['sample']} ({worst['status']}, {state}) at "
            f"{describe(varies, values)}{detail}"
        )
    return lines


DEFAULT_PLOT_METRICS = ("safety_trips", "motor_board_cutouts", "plotvar1_err_rms", "plotvar2_err_rms",
                        "plotvar3_err_rms", "clamp_share")
"""What ``--plot`` draws when ``--plot-metrics`` is not given: those of these that vary, at most
:data:`DEFAULT_PLOT_COUNT`."""
DEFAULT_PLOT_COUNT = 4


def varying(rows: Sequence[Row], name: str) -> bool:
    """Whether ``name`` takes more than one value (NaN counting as one) over ``rows``.

    >>> varying([{"a": 1.0}, {"a": 1.0}], "a"), varying([{"a": 1.0}, {"a": float("nan")}], "a")
    (False, True)
    """
    values = {str(float(r[name])) for r in rows}  # type: ignore[arg-type]
    return len(values) > 1


def plot_metrics(rows: Sequence[Row], asked: Sequence[str] | None) -> tuple[list[str], list[str]]:
    """The metrics to plot and the asked ones left out because every run has the same value.
    Without ``asked``: the first :data:`DEFAULT_PLOT_COUNT` of :data:`DEFAULT_PLOT_METRICS` that
    vary, else every varying metric up to that count, else ``end_s``."""
    if asked:
        kept = [m for m in asked if varying(rows, m)]
        return kept, [m for m in asked if m not in kept]
    kept = [m for m in DEFAULT_PLOT_METRICS if varying(rows, m)]
    kept += [m for m in METRIC_NAMES if m not in kept and varying(rows, m)]
    return kept[:DEFAULT_PLOT_COUNT] or ["end_s"], []


def plot(path: Path, rows: Sequence[Row], varies: Sequence[Vary], *, title: str,
         metrics: Sequence[str] | None = None) -> None:
    """One panel per varied quantity for each of ``metrics`` (default: see :func:`plot_metrics`,
    never one every run has the same value of): the metric of every run against that quantity,
    passed runs in one colour and failed ones in another (:func:`figure`)."""
    import matplotlib.pyplot as plt

    fig = figure(rows, varies, title=title, metrics=metrics)
    fig.savefig(with_parent(path), dpi=100)
    plt.close(fig)


TICKS_PER_AXIS = 4
"""At most this many ticks on each axis of a panel: a panel is about 3 inches wide, and a quantity's
values (0.0125) take a label's width each."""


def figure(rows: Sequence[Row], varies: Sequence[Vary], *, title: str,
           metrics: Sequence[str] | None = None) -> Figure:
    """The figure :func:`plot` saves: at most :data:`TICKS_PER_AXIS` ticks on each axis, and a
    whole-number metric (:data:`INTEGER_METRICS`: trips, cut-outs) ticked at whole numbers only."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    metrics = list(metrics) if metrics else plot_metrics(rows, None)[0]
    n_rows, n_cols = len(metrics), len(varies)
    fig, axes = plt.subplots(n_rows, n_cols, figsize=(3.4 * n_cols + 0.6, 2.3 * n_rows + 0.8), squeeze=False)
    ok = np.array([bool(r["passed"]) for r in rows])
    for i, m in enumerate(metrics):
        y = np.array([float(r[m]) for r in rows], dtype=float)  # type: ignore[arg-type]
        for j, v in enumerate(varies):
            x = np.array([float(r[v.name]) for r in rows], dtype=float)  # type: ignore[arg-type]
            ax = axes[i][j]
            ax.scatter(x[ok], y[ok], s=10, color="tab:blue", label="passed")
            ax.scatter(x[~ok], y[~ok], s=14, color="tab:red", marker="x", label="failed")
            if i == n_rows - 1:
                ax.set_xlabel(v.name)
            if j == 0:
                ax.set_ylabel(m, fontsize=8)
            ax.tick_params(labelsize=7)
            ax.xaxis.set_major_locator(MaxNLocator(nbins=TICKS_PER_AXIS, prune=None))
            ax.yaxis.set_major_locator(MaxNLocator(nbins=TICKS_PER_AXIS, integer=m in INTEGER_METRICS))
            ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7, loc="best")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 1.0 - 0.5 / fig.get_figheight()))
    return fig
