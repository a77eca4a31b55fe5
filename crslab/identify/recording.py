"""Reading a recording of the real arm: the course's Simulink export (``.mat`` or CSV), or crslab's
own ``--csv``, into times and the motor angles it holds.

The course's Simulink model samples ``Simulink_PlotVar1..4`` every 5 ms. What each PlotVar holds
is the lab's choice; a :class:`PlotVarMap` says which PlotVar holds which motor angle (default:
PlotVar1..3 are motors 1..3, as the course's labs do). Layouts read:

- ``.mat`` (``scipy.io.loadmat``): a plain array with time in its first column and PlotVar1..4 in
  the next (Simulink's "Array" save format, what ``load`` gives as one matrix), a structure with
  time (``time`` and ``signals.values``, one or several signals), or separate vectors
  ``Simulink_PlotVar1..4`` / ``PlotVar1..4`` beside ``t``, ``time`` or ``tout``;
- CSV with a header: a time column (``t``, ``t_s``, ``time``, ``t [s]``) and PlotVar1..4 columns
  (``PlotVar1...``, ``Simulink_PlotVar1...``), in seconds and rad; crslab's ``--csv`` is one of them.

Leading samples where every mapped PlotVar is exactly 0 are dropped: Simulink records zeros until
the board's first reply.

>>> m = PlotVarMap.parse("1,2,3")
>>> m.motor_columns, m.joints
((0, 1, 2), (1, 2, 3))
>>> PlotVarMap.parse("3,-,1").joints
(1, 3)
"""

from __future__ import annotations

import csv
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

PLOTVARS = 4
SIMULINK_PERIOD_S = 0.005
"""The course's Simulink model asks the board for the PlotVars every 5 ms."""


class RecordingError(ValueError):
    """A recording that cannot be used; the message names the file and what is wrong."""


@dataclass(frozen=True)
class PlotVarMap:
    """Which PlotVar (1..4) holds motor angle 1, 2 and 3 (None: that joint was not recorded)."""

    plotvar_of_motor: tuple[int | None, int | None, int | None] = (1, 2, 3)

    @classmethod
    def parse(cls, text: str) -> PlotVarMap:
        """``"1,2,3"``: the PlotVar numbers of motors 1, 2, 3; ``-`` for a joint not recorded."""
        parts = [p.strip() for p in text.split(",")]
        if len(parts) != 3:
            raise ValueError(f"--map takes three PlotVar numbers (motors 1, 2, 3; - for none), got {text!r}")
        out: list[int | None] = []
        for p in parts:
            if p in ("-", ""):
                out.append(None)
                continue
            if not p.isdigit() or not 1 <= int(p) <= PLOTVARS:
                raise ValueError(f"--map: {p!r} is not a PlotVar number 1..{PLOTVARS} or -")
            out.append(int(p))
        used = [v for v in out if v is not None]
        if not used:
            raise ValueError("--map names no motor angle")
        if len(set(used)) != len(used):
            raise ValueError(f"--map uses a PlotVar twice: {text!r}")
        return cls(tuple(out))  # type: ignore[arg-type]

    @property
    def joints(self) -> tuple[int, ...]:
        """The joints (1..3) the recording holds."""
        return tuple(j + 1 for j, v in enumerate(self.plotvar_of_motor) if v is not None)

    @property
    def motor_columns(self) -> tuple[int, ...]:
        """The PlotVar columns (0-based) of the recorded joints, in joint order."""
        return tuple(v - 1 for v in self.plotvar_of_motor if v is not None)

    def __str__(self) -> str:
        return ",".join("-" if v is None else str(v) for v in self.plotvar_of_motor)


@dataclass(frozen=True)
class Recording:
    """One recording: sample times (s, the recorder's clock), the four PlotVars (NaN where not
    recorded) and which of them are motor angles."""

    path: Path
    t_s: np.ndarray
    plotvars: np.ndarray
    map: PlotVarMap

    @property
    def joints(self) -> tuple[int, ...]:
        """The joints (1..3) whose motor angles were recorded."""
        return self.map.joints

    @property
    def motor_rad(self) -> np.ndarray:
        """The recorded motor angles (rad), one column per joint of :attr:`joints`."""
        return self.plotvars[:, list(self.map.motor_columns)]

    def window(self, start_s: float | None = None, end_s: float | None = None) -> Recording:
        """The samples from ``start_s`` to ``end_s`` seconds into the recording (None: its start or
        end). Raises :class:`RecordingError` when that leaves fewer than 3 samples."""
        rel = self.t_s - self.t_s[0]
        keep = np.ones(len(rel), dtype=bool)
        if start_s is not None:
            keep &= rel >= start_s - 1e-9
        if end_s is not None:
            keep &= rel <= end_s + 1e-9
        if keep.sum() < 3:
            raise RecordingError(f"{self.path}: fewer than 3 samples between {start_s} and {end_s} s")
        return Recording(self.path, self.t_s[keep], self.plotvars[keep], self.map)

    @property
    def duration_s(self) -> float:
        return float(self.t_s[-1] - self.t_s[0])

    @property
    def period_s(self) -> float:
        """The median sample spacing."""
        return float(np.median(np.diff(self.t_s)))


def read_recording(path: str | Path, plotvars: PlotVarMap = PlotVarMap()) -> Recording:
    """Read ``path`` (``.mat`` or ``.csv``) and keep the motor angles ``plotvars`` names. Raises
    :class:`RecordingError` (one line, naming the file) for anything unusable."""
    path = Path(path)
    if not path.is_file():
        raise RecordingError(f"{path}: no such recording")
    suffix = path.suffix.lower()
    if suffix == ".mat":
        t, plot = _read_mat(path)
    elif suffix in (".csv", ".txt"):
        t, plot = _read_csv(path)
    else:
        raise RecordingError(f"{path}: not a recording crslab reads (.mat from Simulink, or .csv)")
    for col in plotvars.motor_columns:
        if col >= plot.shape[1] or np.all(np.isnan(plot[:, col])):
            raise RecordingError(f"{path}: has no PlotVar{col + 1} (--map {plotvars} asks for it)")
    angles = plot[:, list(plotvars.motor_columns)]
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(angles))):
        raise RecordingError(f"{path}: has missing or non-numeric values in the time or a motor column")
    start = 0
    while start < len(t) and np.all(angles[start] == 0.0):
        start += 1  # Simulink records zeros until the board first answers
    t, plot = t[start:], plot[start:]
    if len(t) < 3:
        raise RecordingError(f"{path}: fewer than 3 samples after the leading zeros")
    if np.any(np.diff(t) <= 0):
        raise RecordingError(f"{path}: the time column does not increase")
    return Recording(path, t, plot, plotvars)


# -- .mat ------------------------------------------------------------------------------------------
_TIME_NAMES = ("t", "t_s", "time", "tout")
_PLOTVAR_RE = re.compile(r"^(?:simulink_)?plotvar([1-4])(?![0-9])", re.IGNORECASE)


def _read_mat(path: Path) -> tuple[np.ndarray, np.ndarray]:
    from scipy.io import loadmat

    try:
        mat = loadmat(str(path), squeeze_me=True, struct_as_record=False)
    except Exception as exc:  # noqa: BLE001 - scipy raises many kinds for a bad file
        raise RecordingError(f"{path}: not a MATLAB .mat file scipy can read ({exc})") from None
    names = {k: v for k, v in mat.items() if not k.startswith("__")}
    # separate PlotVar vectors (or structures) beside a time vector
    singles: dict[int, np.ndarray] = {}
    time: np.ndarray | None = None
    for name, value in names.items():
        m = _PLOTVAR_RE.match(name)
        if m:
            t_own, v = _struct_or_array(value)
            singles[int(m.group(1))] = np.asarray(v, dtype=float).reshape(-1)
            time = t_own if t_own is not None else time
        elif name.lower() in _TIME_NAMES and np.ndim(value) == 1:
            time = np.asarray(value, dtype=float)
    if singles:
        n = len(next(iter(singles.values())))
        plot = np.full((n, PLOTVARS), np.nan)
        for k, v in singles.items():
            if len(v) != n:
                raise RecordingError(f"{path}: its PlotVar vectors differ in length")
            plot[:, k - 1] = v
        if time is None:
            time = np.arange(n) * SIMULINK_PERIOD_S
        if len(time) != n:
            raise RecordingError(f"{path}: its time vector has {len(time)} samples, the PlotVars {n}")
        return time, plot
    # one variable: a plain array or a structure with time
    candidates = [(k, v) for k, v in names.items() if _is_struct(v) or np.ndim(v) == 2]
    if len(candidates) != 1:
        found = ", ".join(names) or "nothing"
        raise RecordingError(f"{path}: expected one Simulink recording (an array with time in column 1, "
                             f"or a structure with time) or Simulink_PlotVar1..4 vectors; found {found}")
    name, value = candidates[0]
    t, values = _struct_or_array(value)
    values = np.atleast_2d(np.asarray(values, dtype=float))
    if t is None:  # a plain array: time first
        if values.shape[1] < 2:
            raise RecordingError(f"{path}: {name} has {values.shape[1]} column; expected time and PlotVars")
        t, values = values[:, 0], values[:, 1:]
    if values.shape[0] != len(t):
        values = values.T if values.shape[1] == len(t) else values
    if values.shape[0] != len(t):
        raise RecordingError(f"{path}: {name} has {len(t)} times but {values.shape[0]} rows of values")
    plot = np.full((len(t), PLOTVARS), np.nan)
    plot[:, :min(PLOTVARS, values.shape[1])] = values[:, :PLOTVARS]
    return np.asarray(t, dtype=float), plot


def _is_struct(value: object) -> bool:
    return hasattr(value, "_fieldnames")


def _struct_or_array(value: object) -> tuple[np.ndarray | None, np.ndarray]:
    """(time or None, values) of a Simulink structure (with or without time) or an array."""
    if not _is_struct(value):
        return None, np.asarray(value, dtype=float)
    fields = value._fieldnames  # type: ignore[attr-defined]
    time = np.asarray(value.time, dtype=float).reshape(-1) if "time" in fields else None
    if time is not None and time.size == 0:
        time = None
    signals = value.signals if "signals" in fields else value  # type: ignore[attr-defined]
    parts = signals if isinstance(signals, np.ndarray) else [signals]
    columns = [np.asarray(s.values, dtype=float) for s in parts]  # type: ignore[attr-defined]
    columns = [c.reshape(len(c), -1) if c.ndim else c.reshape(1, 1) for c in columns]
    return time, np.hstack(columns)


# -- .csv ------------------------------------------------------------------------------------------
def _read_csv(path: Path) -> tuple[np.ndarray, np.ndarray]:
    try:
        with path.open(newline="") as f:
            rows = list(csv.reader(f))
    except (OSError, UnicodeDecodeError) as exc:
        raise RecordingError(f"{path}: cannot be read ({exc})") from None
    if len(rows) < 2:
        raise RecordingError(f"{path}: no header and samples")
    header = [h.strip() for h in rows[0]]
    time_col = next((i for i, h in enumerate(header)
                     if h.lower().split(" [")[0] in _TIME_NAMES), None)
    if time_col is None:
        raise RecordingError(f"{path}: no time column (t, t_s, time or 't [s]') in its header")
    cols: dict[int, int] = {}
    for i, h in enumerate(header):
        m = _PLOTVAR_RE.match(h)
        if m:
            cols.setdefault(int(m.group(1)), i)
    if not cols:
        raise RecordingError(f"{path}: no PlotVar columns (PlotVar1..4 or Simulink_PlotVar1..4) in its "
                             "header")
    try:
        data = np.array([[float(r[i]) if r[i].strip() else np.nan for i in range(len(header))]
                         for r in rows[1:] if r], dtype=float)
    except (ValueError, IndexError):
        raise RecordingError(f"{path}: a row is not numbers in every column") from None
    plot = np.full((len(data), PLOTVARS), np.nan)
    for k, i in cols.items():
        plot[:, k - 1] = data[:, i]
    return data[:, time_col], plot
