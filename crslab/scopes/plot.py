"""``crslab plot``: draw a ``--csv`` file for a lab report, one panel per signal group.

Columns are recognised by their header cell (``theta1motor [rad]``, see
:mod:`crslab.scopes.signals`); a panel is drawn for each group that has at least one column
(a group that is not ``always`` drawn, the push, only when a value is not 0), titled with the
group and its y axis labelled with the unit. Time (s) runs along the bottom.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from crslab.output_paths import with_parent
from crslab.scopes.signals import GROUPS, SIGNALS, TORQUE, WORLD_GROUPS, WORLD_SIGNALS, Signal

TIME_COLUMN = "t [s]"


class PlotError(Exception):
    """The CSV cannot be plotted (missing, not a crslab scope CSV, empty)."""


def read_scope_csv(path: Path) -> tuple[np.ndarray, dict[Signal, np.ndarray]]:
    """Time (s) and each known signal's values from a ``--csv`` file."""
    import pyarrow as pa
    import pyarrow.csv as pacsv

    try:
        table = pacsv.read_csv(path)
    except FileNotFoundError:
        raise PlotError(f"{path}: no such file") from None
    except (pa.ArrowInvalid, OSError, UnicodeDecodeError) as exc:
        raise PlotError(f"{path}: not a CSV file ({str(exc).splitlines()[0]})") from None
    names = table.column_names
    known = {s.csv_name: s for s in SIGNALS + WORLD_SIGNALS}
    found = {known[n]: n for n in names if n in known}
    if TIME_COLUMN not in names or not found:
        raise PlotError(f"{path}: not a crslab scope CSV (no '{TIME_COLUMN}' column and signal columns; "
                        "write one with 'crslab sim --csv FILE')")
    if table.num_rows == 0:
        raise PlotError(f"{path}: holds no rows")
    try:
        t = table[TIME_COLUMN].to_numpy().astype(float)
        values = {s: table[n].to_numpy().astype(float) for s, n in found.items()}
    except (pa.ArrowInvalid, ValueError, TypeError) as exc:
        raise PlotError(f"{path}: a column holds something other than numbers ({exc})") from None
    return t, values


def scope_figure(t: np.ndarray, values: dict[Signal, np.ndarray], title: str) -> object:
    """A matplotlib figure (Agg) with one panel per signal group present in ``values``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    groups = [g for g in GROUPS + WORLD_GROUPS
              if any(s.group == g and (g.always or np.any(v != 0)) for s, v in values.items())]
    fig, axes = plt.subplots(len(groups), 1, sharex=True, squeeze=False,
                             figsize=(10, 2.2 * len(groups) + 0.8), layout="constrained")
    for ax, group in zip(axes[:, 0], groups):
        members = [(s, v) for s, v in values.items() if s.group == group]
        if group.unit == "0/1":  # digital signals: one lane each, as a logic analyser shows them
            for lane, (s, v) in enumerate(members):
                ax.plot(t, 0.8 * v + 1.2 * lane, label=s.name, linewidth=1.0, drawstyle="steps-post")
            ax.set_yticks([1.2 * k + 0.4 for k in range(len(members))], [s.name for s, _ in members])
            ax.set_ylabel("0/1 (a lane each)")
        else:
            for s, v in members:
                style = {"linestyle": "--"} if group == TORQUE and s.column == "tau_applied" else {}
                ax.plot(t, v, label=s.name, linewidth=1.0, **style)
            ax.set_ylabel(group.unit)
            ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
        ax.set_title(group.title, loc="left", fontsize=10)
        ax.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel("time (s)")
    fig.suptitle(title, fontsize=11)
    return fig


def plot_scope_csv(path: Path, out: Path, *, t_from: float | None = None, t_to: float | None = None,
                   title: str | None = None) -> list[str]:
    """Draw ``path`` into the image ``out`` (format from its suffix); returns the panels' titles."""
    import matplotlib.pyplot as plt

    t, values = read_scope_csv(path)
    keep = np.ones(len(t), bool)
    if t_from is not None:
        keep &= t >= t_from
    if t_to is not None:
        keep &= t <= t_to
    if not keep.any():
        raise PlotError(f"{path}: no rows between {t_from} s and {t_to} s (the file spans "
                        f"{t[0]:g} to {t[-1]:g} s)")
    fig = scope_figure(t[keep], {s: v[keep] for s, v in values.items()}, title or path.name)
    try:
        fig.savefig(with_parent(out), dpi=110)
    except (OSError, ValueError) as exc:
        raise PlotError(f"{out}: cannot write the figure ({exc})") from None
    finally:
        plt.close(fig)
    return [ax.get_title(loc="left") for ax in fig.axes]
