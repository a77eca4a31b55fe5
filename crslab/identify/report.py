"""What ``crslab identify`` shows and writes: the residual table, the fitted values, the plant
file's header and the real-against-simulated plot."""

from __future__ import annotations

import datetime
import textwrap
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from crslab import __version__
from crslab.identify.fit import FitResult, Source
from crslab.output_paths import with_parent


def residual_table(result: FitResult, sources: Sequence[Source]) -> list[str]:
    """One line per recording and joint: RMS of (sim - real) before and after, and the max after;
    then one line per friction table and joint: its numbers as tabled, as the plant predicted them
    before and after (the course's method on the plant), and the RMS gap."""
    lines = []
    if sources:
        lines.append("residual (sim - real), rad          RMS before   RMS after   max after")
    for src, before, after, mx in zip(sources, result.rms_before, result.rms_after, result.max_after):
        for k, joint in enumerate(src.recording.joints):
            name = src.recording.path.name[:26]
            lines.append(f"  {name:26s} joint {joint}  {before[k]:10.4f}  {after[k]:10.4f}  {mx[k]:10.4f}")
    for tr in result.tables:
        if lines:
            lines.append("")
        lines.append(f"friction table {tr.source.name[:40]} (+- {tr.source.table.uncertainty:.0%}): "
                     f"Vpos Vneg Cpos Cneg, command units")
        numbers = tr.source.numbers()
        tabled, before, after = tr.source.tabled(), tr.before, tr.after
        for joint in sorted({j for j, _ in numbers}):
            idx = [i for i, (j, _) in enumerate(numbers) if j == joint]
            lines.append(f"  joint {joint} tabled  " + "".join(f"{tabled[i]:9.4f}" for i in idx))
            lines.append("          before  " + "".join(f"{before[i]:9.4f}" for i in idx)
                         + "   gaps " + " ".join(f"{before[i] / tabled[i] - 1:+.1%}" for i in idx))
            lines.append("          after   " + "".join(f"{after[i]:9.4f}" for i in idx)
                         + "   gaps " + " ".join(f"{after[i] / tabled[i] - 1:+.1%}" for i in idx))
        lines.append(f"  RMS gap {tr.rms_gap(False):.1%} before, {tr.rms_gap(True):.1%} after")
    return lines


def values_table(result: FitResult) -> list[str]:
    """One line per fitted value: start, fitted, uncertainty."""
    lines = ["fitted value                     start       fitted   +- 1 sd"]
    for f in [*result.values, *result.nuisance]:
        note = "  (at its bound)" if f.at_bound else ""
        lines.append(f"  {f.name:28s} {f.start:10.5g}  {f.value:10.5g}  {f.sigma:8.2g}{note}")
    return lines


def plant_file_header(result: FitResult, sources: Sequence[Source], names: Sequence[str]) -> str:
    """The comment block at the top of the plant file: where the values came from."""
    when = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    out = [f"crslab plant parameters, identified by crslab {__version__} on {when}.",
           "Use: crslab sim --plant THIS_FILE (also record, check, grade and the crslab_check fixture).",
           ""]
    if sources:
        out.append("Recordings (lab that produced each, uncertainty per sample):")
    for src in sources:
        out.append(f"  {src.recording.path} ({src.config.build.source.name}), "
                   f"PlotVars of motors 1-3: {src.recording.map}, +- {src.sigma_rad:g} rad")
    if result.tables:
        out.append("Friction tables (relative uncertainty of each number):")
    for tr in result.tables:
        out.append(f"  {tr.source.path} (+- {tr.source.table.uncertainty:.0%})")
    out += ["", "Fitted (everything else as the starting plant):"]
    out += textwrap.wrap(", ".join(names), width=96, initial_indent="  ", subsequent_indent="  ") + [""]
    out += values_table(result) + [""] + residual_table(result, sources)
    return "\n".join(out)


def plot_fit(path: Path, result: FitResult, sources: Sequence[Source]) -> None:
    """Real against simulated motor angles, per joint, two columns per recording: the angles (the
    recording, the starting plant and the fitted one) and the residual (sim - real) of both, with
    their RMS."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if not sources:  # tables alone: crslab friction plots those
        return
    rows = max(len(s.recording.joints) for s in sources)
    fig, axes = plt.subplots(rows, 2 * len(sources), figsize=(12 * len(sources), 2.6 * rows), squeeze=False,
                             sharex="col")
    for c, (src, before, after, rb, ra) in enumerate(zip(sources, result.sim_before, result.sim_after,
                                                       result.rms_before, result.rms_after)):
        rec = src.recording
        t = rec.t_s - rec.t_s[0]
        for r, joint in enumerate(rec.joints):
            ax, res = axes[r][2 * c], axes[r][2 * c + 1]
            ax.plot(t, rec.motor_rad[:, r], ".", color="black", ms=2.0, label="real")
            ax.plot(t, before[:, r], "-", color="0.6", lw=1.0, label="start")
            ax.plot(t, after[:, r], "-", color="tab:red", lw=1.0, label="fitted")
            ax.set_ylabel(f"motor {joint} [rad]")
            res.plot(t, before[:, r] - rec.motor_rad[:, r], "-", color="0.6", lw=0.8,
                     label=f"start (RMS {rb[r]:.4f} rad)")
            res.plot(t, after[:, r] - rec.motor_rad[:, r], "-", color="tab:red", lw=0.8,
                     label=f"fitted (RMS {ra[r]:.4f} rad)")
            res.set_ylabel(f"sim - real, motor {joint} [rad]")
            for a in (ax, res):
                a.grid(True, alpha=0.3)
                a.legend(loc="best", fontsize=7)
        title = f"{rec.path.name} ({src.config.build.source.name})"
        axes[0][2 * c].set_title(title, fontsize=9)
        axes[0][2 * c + 1].set_title(f"{title}: residual", fontsize=9)
        for a in axes[len(rec.joints) - 1][2 * c:2 * c + 2]:
            a.set_xlabel("time in the recording [s]")
    fig.tight_layout()
    fig.savefig(with_parent(path), dpi=110)
    plt.close(fig)


def rms_overall(result: FitResult) -> tuple[float, float]:
    """Overall RMS before and after, every recording and joint together (NaN without recordings)."""
    def overall(parts: Sequence[np.ndarray]) -> float:
        return float(np.sqrt(np.mean(np.concatenate([p ** 2 for p in parts])))) if parts else float("nan")

    return overall(result.rms_before), overall(result.rms_after)
