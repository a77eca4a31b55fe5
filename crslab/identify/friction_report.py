"""What ``crslab friction`` shows: the table in the course's units beside a reference table (the
course's), and the plot of command against speed per joint."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from crslab.identify.friction_table import KEYS, FrictionTable, relative_gaps


def table_lines(measured: FrictionTable, reference: FrictionTable | None = None,
                reference_name: str = "course") -> list[str]:
    """Per joint: the measured Vpos, Vneg (units s/rad), Cpos, Cneg (units) and each line's fit RMS;
    beneath, the reference's numbers and the gap to them (%).

    >>> from crslab.identify.friction_table import JointRow, Line
    >>> t = FrictionTable({1: JointRow(Line(0.26, 0.36, 0.001), Line(0.25, -0.3, 0.002))})
    >>> for line in table_lines(t, t)[1:]: print(line)
    joint 1     0.2600    0.2500    0.3600   -0.3000     0.0010 / 0.0020
      course    0.2600    0.2500    0.3600   -0.3000
      gap        +0.0%     +0.0%     +0.0%     +0.0%
    """
    out = [f"{'':8s}{'Vpos':>10s}{'Vneg':>10s}{'Cpos':>10s}{'Cneg':>10s}     fit RMS (+ / -)"]
    gaps = relative_gaps(measured, reference) if reference is not None else {}
    for j in sorted(measured.rows):
        row = measured.rows[j]
        values = "".join(f"{measured.value(j, k):10.4f}" for k in KEYS)
        out.append(f"joint {j} {values}     {row.positive.rms_units:.4f} / {row.negative.rms_units:.4f}")
        if reference is not None and j in reference.rows:
            out.append(f"  {reference_name:6s}" + "".join(f"{reference.value(j, k):10.4f}" for k in KEYS))
            out.append(f"  {'gap':6s}" + "".join(f"{gaps[(j, k)]:+9.1%} " for k in KEYS).rstrip())
    return out


def plot_table(path: Path, measured: FrictionTable, reference: FrictionTable | None = None,
               measured_name: str = "crslab", reference_name: str = "course") -> None:
    """Command against motor speed, one panel per joint: the measured points, their lines, and the
    reference's lines (dashed), both directions."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    joints = sorted(measured.rows)
    fig, axes = plt.subplots(1, len(joints), figsize=(5.2 * len(joints), 4.2), squeeze=False)
    top = max([abs(p.speed_rad_s) for p in measured.points] + list(measured.speeds_rad_s)) * 1.05
    for ax, j in zip(axes[0], joints):
        pts = [p for p in measured.points if p.joint == j]
        if pts:
            ax.plot([p.speed_rad_s for p in pts], [p.command_units for p in pts], "o", color="tab:red", ms=4,
                    label=f"{measured_name}: mean command at each speed")
        for sign in (1, -1):
            w = np.linspace(0.0, top, 50) * sign
            line = measured.rows[j].positive if sign > 0 else measured.rows[j].negative
            ax.plot(w, line.slope * w + line.intercept, "-", color="tab:red", lw=1.2,
                    label=f"{measured_name}: its lines" if sign > 0 else None)
            if reference is not None and j in reference.rows:
                ref = reference.rows[j].positive if sign > 0 else reference.rows[j].negative
                ax.plot(w, ref.slope * w + ref.intercept, "--", color="black", lw=1.0,
                        label=f"{reference_name}'s lines" if sign > 0 else None)
        ax.axhline(0.0, color="0.8", lw=0.6)
        ax.axvline(0.0, color="0.8", lw=0.6)
        ax.set_title(f"joint {j}", fontsize=10)
        ax.set_xlabel("motor speed [rad/s]")
        ax.set_ylabel("command [units]")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper left", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
