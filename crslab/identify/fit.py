"""Fitting the plant to experiments: bounded least squares over named plant values.

Two kinds of experiment, each with its uncertainty, fit together:

- a recording of the real arm (:class:`Source`): the residual is (simulated - recorded) motor
  angle at every recorded sample, with the lab's PlotVars simulated by running the very lab that
  produced the recording. Each recording has its own alignment terms (phase and drift, see
  :mod:`crslab.identify.align`), fitted with the plant but bounded to where the lab's own signals
  allow; optionally its true resting pose (``fit_rest``: the lab's offsets are known only to
  about 0.01 rad, so the fit may move each by up to :data:`REST_RANGE_RAD`);
- a friction table (:class:`TableSource`, the course's Lab 3 method's result): the residual is
  (predicted - tabled) for each of its numbers, the prediction being the lines the method finds on
  the plant (:func:`crslab.identify.friction_table.predict`).

Each residual is divided by its experiment's uncertainty: a recording's ``sigma_rad`` (how closely
the model is expected to follow it, per sample) times the square root of its residuals'
autocorrelation time at the start (:func:`autocorrelation_time`: neighbouring samples of a model
error are not independent, so a recording counts as its number of independent stretches, not of
samples), a table's relative uncertainty times each number. So a 12-number table and a
6000-sample recording weigh what their information is worth.

The plant values are the physical ones of :class:`crslab.plant.plant_params.PlantParams`, each
with a bound that keeps it physical (:data:`BOUNDS`). Derivatives are forward differences with a
step per value (a simulated run per value, several at once); the alignment terms' derivatives
need no run. scipy's ``least_squares`` (trust region reflective) takes it from there.

Uncertainty: the Gauss-Newton covariance ``(J^T J)^-1`` of the weighted residuals, scaled by
the reduced chi-square (over the effective number of residuals) when the experiments disagree with
the model by more than their stated uncertainties, reported as one standard deviation.

Static friction that is not fitted keeps its gap to the Coulomb value it goes with (a plant without
stiction, ``Spos = Cpos``, stays without).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from crslab.framework_facts import TICKS_PER_S
from crslab.identify import align as al
from crslab.identify.friction_table import KEYS, FrictionTable, predict
from crslab.identify.recording import Recording
from crslab.identify.runs import IdentifyRun, Runner
from crslab.plant.model import holding_torques_nm
from crslab.plant.plant_params import NAMES, PlantParams, PlantParamsError
from crslab.worker.config import RunConfig

# name stem -> (low, high, finite-difference step): what is physically plausible for the CRS arm
BOUNDS: dict[str, tuple[float, float, float]] = {
    "stall_nm": (3.0, 60.0, 0.18),
    "backemf": (0.0, 30.0, 0.06),
    "drive_lag_s": (0.0, 0.05, 0.0005),
    "coulomb_pos": (0.0, 6.0, 0.06),
    "coulomb_neg": (-6.0, 0.0, 0.06),
    "viscous_pos": (0.0, 6.0, 0.06),
    "viscous_neg": (0.0, 6.0, 0.06),
    "static_pos": (0.0, 6.0, 0.06),
    "static_neg": (-6.0, 0.0, 0.06),
    "friction_transition_rad_s": (0.005, 0.2, 0.002),
    "rotor_inertia": (0.0, 1.0, 0.005),
    "motor_gain": (1.0, 20.0, 0.06),
    "friction": (0.1, 10.0, 0.02),
    "mass": (0.2, 5.0, 0.02),
    "payload_kg": (0.0, 5.0, 0.02),
}
GROUPS: dict[str, tuple[str, ...]] = {
    "drive": tuple(f"{stem}{m}" for stem in ("stall_nm", "backemf") for m in (1, 2, 3)) + ("drive_lag_s",),
    "friction": tuple(f"{stem}{m}" for stem in ("coulomb_pos", "coulomb_neg", "viscous_pos", "viscous_neg")
                      for m in (1, 2, 3)),
    "static": tuple(f"{stem}{m}" for stem in ("static_pos", "static_neg") for m in (1, 2, 3)),
    "inertia": tuple(f"rotor_inertia{m}" for m in (1, 2, 3)),
}
"""Names of groups of values (``--fit drive,friction,static,inertia``, the default)."""
DEFAULT_FIT = ("drive", "friction", "static", "inertia")
RECORDING_SIGMA_RAD = 0.005
"""How closely the model is expected to follow a recording, per sample (rad): its uncertainty
when none is given. Model error, not noise: about the repeatable wobble at each step's start that a
rigid model cannot follow (models/crs_arm/README.md), half issue 23's 0.01 rad target."""
STATIC_PRIOR_NM = 0.5
"""A fitted static value is held to its Coulomb value within about this much (N.m, one standard
deviation) where the experiments say nothing about it: few recordings show a joint breaking free
in both directions, and a table says nothing of it."""
TABLE_ONLY = ("coulomb_pos", "coulomb_neg", "viscous_pos", "viscous_neg", "static_pos", "static_neg",
              "friction_transition_rad_s", "motor_gain", "friction")
"""What a friction table alone can tell (the friction and the command's torque)."""
HOLD_MARGIN = 1.02
"""The dry friction a fit may end on must hold the arm at its resting pose with this margin: the
real arm rests where it is put with zero torque (docs/framework.md section 11), which the recordings
may not show."""
REST_RANGE_RAD = 0.02
PHASE_STEP_MS = 0.05
DRIFT_STEP = 2e-6
XTOL = 1e-10
FTOL = 1e-10
REST_STEP_RAD = 0.002
WARMUP_S = 3.0
"""A recording is placed no earlier than this into the run: the lab's first moves from rest are
not what a recording of a run that 'had been going for a while' shows."""
MIN_DURATION_S = 1.0
"""A recording shorter than this holds no complete step response to fit."""


class FitError(ValueError):
    """Input the fit cannot use (one line)."""


@dataclass(frozen=True)
class Fitted:
    """One fitted value: its name, where the fit started, where it ended and its uncertainty
    (one standard deviation; ``at_bound`` when it ended on a bound)."""

    name: str
    start: float
    value: float
    sigma: float
    at_bound: bool = False


@dataclass(frozen=True)
class Source:
    """One recording with the prepared lab run that produced it, and its uncertainty."""

    recording: Recording
    config: RunConfig
    lab_offsets: tuple[float, float, float]
    """The resting pose the lab's offsets describe (motor angles, rad): the run's default."""
    sigma_rad: float = RECORDING_SIGMA_RAD

    @property
    def name(self) -> str:
        return self.recording.path.name


@dataclass(frozen=True)
class TableSource:
    """One friction table (its uncertainty is the table's own, relative)."""

    table: FrictionTable
    path: str

    @property
    def name(self) -> str:
        return self.path.rsplit("/", 1)[-1]

    def numbers(self) -> list[tuple[int, str]]:
        """The (joint, key) of every number, in residual order."""
        return [(j, k) for j in sorted(self.table.rows) for k in KEYS]

    def predicted(self, plant: PlantParams) -> np.ndarray:
        """The numbers the course's method would find on ``plant``, in :meth:`numbers` order."""
        pred = predict(plant, self.table.speeds_rad_s, sorted(self.table.rows))
        return np.array([pred.value(j, k) for j, k in self.numbers()])

    def tabled(self) -> np.ndarray:
        return np.array([self.table.value(j, k) for j, k in self.numbers()])

    def sigmas(self) -> np.ndarray:
        return np.maximum(np.abs(self.tabled()) * self.table.uncertainty, 1e-6)


@dataclass(frozen=True)
class TableResult:
    """A table's numbers as tabled and as predicted before and after the fit."""

    source: TableSource
    before: np.ndarray
    after: np.ndarray

    def gaps(self, after: bool = True) -> np.ndarray:
        """Predicted / tabled - 1 for each number."""
        return (self.after if after else self.before) / self.source.tabled() - 1.0

    def rms_gap(self, after: bool = True) -> float:
        return float(np.sqrt(np.mean(self.gaps(after) ** 2)))


@dataclass
class FitResult:
    plant: PlantParams
    start_plant: PlantParams
    values: list[Fitted]
    nuisance: list[Fitted]
    alignments: list[al.Alignment]
    rms_before: list[np.ndarray]
    """Per recording: RMS of (sim - real) per recorded joint, rad, at the start (alignment fitted)."""
    rms_after: list[np.ndarray]
    max_after: list[np.ndarray]
    sim_before: list[np.ndarray]
    sim_after: list[np.ndarray]
    rests: list[tuple[float, float, float]]
    runs: int
    message: str
    tables: list[TableResult] = field(default_factory=list)
    chi2_reduced: float = float("nan")
    """The weighted residual's sum of squares over the effective number of residuals less the
    values fitted: about 1 when the experiments agree with the model as their uncertainties say."""


def names_to_fit(spec: Sequence[str], joints: set[int]) -> list[str]:
    """Expand groups; leave out per-motor values of motors no recording has. Raises
    :class:`FitError` for an unknown name."""
    out: list[str] = []
    for item in spec:
        expanded = GROUPS.get(item, (item,))
        for name in expanded:
            if name not in NAMES:
                known = ", ".join([*GROUPS, *NAMES])
                raise FitError(f"cannot fit {name!r}; the names are {known}")
            index = NAMES[name].index
            if index is not None and NAMES[name].field != "friction_scale" and index + 1 not in joints:
                continue
            if name not in out:
                out.append(name)
    if not out:
        raise FitError("nothing to fit")
    return out


@functools.lru_cache(maxsize=16)
def _holding(rest: tuple[float, float, float], plant: PlantParams) -> tuple[float, ...]:
    return tuple(float(v) for v in holding_torques_nm(rest, plant))


def _holding_bounds(name: str, low: float, high: float, sources: Sequence[Source],
                    plant: PlantParams, names: Sequence[str]) -> tuple[float, float]:
    """Tighten a dry-friction bound so the arm rests at every recording's resting pose: a static
    value's own, or a Coulomb value's whose static value follows it (not fitted itself)."""
    stem, motor = name.rstrip("0123456789"), name[len(name.rstrip("0123456789")):]
    if not motor:
        return low, high
    side = stem.rsplit("_", 1)[-1]
    gap = 0.0
    if stem in ("coulomb_pos", "coulomb_neg"):
        if f"static_{side}{motor}" in names:
            return low, high
        gap = plant.value(f"static_{side}{motor}") - plant.value(name)  # the static value stays this far
    elif stem not in ("static_pos", "static_neg"):
        return low, high
    m = int(motor) - 1
    for src in sources:
        need = _holding(src.lab_offsets, plant)[m] * HOLD_MARGIN
        if side == "pos" and need < 0:
            low = max(low, -need - gap)
        elif side == "neg" and need > 0:
            high = min(high, -need - gap)
    return low, high


def _bounds(name: str, value: float) -> tuple[float, float, float]:
    stem = name.rstrip("0123456789") or name
    if stem in BOUNDS:
        low, high, step = BOUNDS[stem]
    else:
        spec = NAMES[name]
        low, high, step = spec.low, spec.high, max(abs(value) * 0.01, 1e-3)
    return low, high, step


Terms = tuple[float, float, tuple[float, float, float]]


class Problem:
    """The residual and its derivatives for one set of sources and fitted names."""

    def __init__(self, sources: Sequence[Source], names: Sequence[str], start: PlantParams,
                 runner: Runner, *, fit_rest: bool = False, tables: Sequence[TableSource] = ()) -> None:
        self.sources = list(sources)
        self.tables = list(tables)
        self.names = list(names)
        # one over each recording's uncertainty; weigh_recordings() adds its autocorrelation
        self.weights = [1.0 / s.sigma_rad for s in self.sources]
        self.static_names = [n for n in self.names if n.startswith("static_")]
        self.start = start
        self.runner = runner
        self.fit_rest = fit_rest
        self.alignments: list[al.Alignment] = []
        self.lengths: list[int] = []
        lows, highs, steps, x0 = [], [], [], []
        for n in self.names:
            v = start.value(n)
            low, high, step = _bounds(n, v)
            low, high = _holding_bounds(n, low, high, sources, start, self.names)
            if not low <= v <= high:
                v = min(max(v, low), high)  # a start that could not hold the arm at rest starts where it can
            lows.append(low)
            highs.append(high)
            steps.append(step)
            x0.append(v)
        self.n_plant = len(self.names)
        self.lows, self.highs, self.steps, self.x0 = lows, highs, steps, x0
        self._cache: dict[bytes, list[np.ndarray]] = {}

    # -- layout of x ----------------------------------------------------------------------------
    def per_source(self) -> int:
        return 4 if self.fit_rest else 2

    def split(self, x: np.ndarray) -> tuple[PlantParams, list[Terms]]:
        """The plant and, per recording, its (phase ms, drift, resting pose) that ``x`` holds."""
        values = dict(zip(self.names, map(float, x[: self.n_plant])))
        for name in list(values):  # a static value not fitted keeps its gap to its Coulomb value
            stem, motor = name.rstrip("0123456789"), name[len(name.rstrip("0123456789")):]
            if stem in ("coulomb_pos", "coulomb_neg"):
                static = f"static_{stem.rsplit('_', 1)[1]}{motor}"
                if static not in values:
                    values[static] = self.start.value(static) + values[name] - self.start.value(name)
        plant = self.start.with_values(values)
        terms = []
        k = self.n_plant
        for src in self.sources:
            phase, drift = float(x[k]), float(x[k + 1])
            rest = src.lab_offsets
            if self.fit_rest:
                rest = (rest[0], rest[1] + float(x[k + 2]), rest[2] + float(x[k + 3]))
            terms.append((phase, drift, rest))
            k += self.per_source()
        return plant, terms

    # -- set-up: coarse alignment -----------------------------------------------------------------
    def place(self) -> None:
        """Find each recording's start on a long run of the starting plant and bound its phase and
        drift; afterwards every run is just long enough for its recording."""
        runs = []
        for src in self.sources:
            rec = src.recording
            search = min(rec.duration_s, 10.0) + 1.0
            end = int((WARMUP_S + search + rec.duration_s * (1 + al.MAX_DRIFT)) * TICKS_PER_S) + 20
            runs.append(IdentifyRun(src.config, self.start, src.lab_offsets, end))
        plots = self.runner.run_all(runs)
        for src, plot, run in zip(self.sources, plots, runs):
            rec = src.recording
            latest = run.end_tick - int(rec.duration_s * TICKS_PER_S * (1 + al.MAX_DRIFT)) - 15
            start = al.coarse_start(plot, rec.plotvars, rec.t_s, int(WARMUP_S * TICKS_PER_S), latest)
            alignment = al.fine_bounds(plot, rec.plotvars, rec.t_s, start, rec.map.motor_columns,
                                       rec.period_s * 1000.0)
            self.alignments.append(alignment)
            ticks = 5 + 2 * rec.period_s * TICKS_PER_S + rec.duration_s * TICKS_PER_S * (1 + al.MAX_DRIFT)
            self.lengths.append(start + int(math.ceil(ticks)) + 5)
        rest = 2 if self.fit_rest else 0
        for a in self.alignments:
            self.x0 += [a.phase_ms, a.drift] + [0.0] * rest
            self.lows += [a.phase_bounds[0], a.drift_bounds[0]] + [-REST_RANGE_RAD] * rest
            self.highs += [a.phase_bounds[1], a.drift_bounds[1]] + [REST_RANGE_RAD] * rest
            self.steps += [PHASE_STEP_MS, DRIFT_STEP] + [REST_STEP_RAD] * rest
            if a.phase_bounds[0] == a.phase_bounds[1]:  # least_squares needs room
                self.lows[-self.per_source()] -= 1e-6
                self.highs[-self.per_source()] += 1e-6
            if a.drift_bounds[0] == a.drift_bounds[1]:
                self.lows[-self.per_source() + 1] -= 1e-9
                self.highs[-self.per_source() + 1] += 1e-9

    # -- residuals ----------------------------------------------------------------------------------
    def _runs(self, x: np.ndarray) -> list[np.ndarray]:
        key = np.asarray(x, dtype=float).tobytes()
        if key not in self._cache:
            self._cache = {key: self.runner.run_all(self._lab_runs(x)) if self.sources else []}
        return self._cache[key]

    def simulated(self, x: np.ndarray, plots: list[np.ndarray] | None = None) -> list[np.ndarray]:
        """Per recording, the simulated motor angles at its samples (columns: its joints)."""
        plots = self._runs(x) if plots is None else plots
        _, terms = self.split(x)
        out = []
        for src, plot, a, (phase, drift, _) in zip(self.sources, plots, self.alignments, terms):
            rec = src.recording
            sim = al.sample(plot[:, list(rec.map.motor_columns)], rec.t_s, a.start_tick, phase, drift)
            out.append(sim)
        return out

    def residual(self, x: np.ndarray, plots: list[np.ndarray] | None = None) -> np.ndarray:
        """Every experiment's residual over its uncertainty: the recordings' samples, then the
        tables' numbers."""
        sims = self.simulated(x, plots) if self.sources else []
        parts = [w * (s - src.recording.motor_rad).ravel()
                 for s, src, w in zip(sims, self.sources, self.weights)]
        if self.tables or self.static_names:
            plant, _ = self.split(x)
            parts += [(t.predicted(plant) - t.tabled()) / t.sigmas() for t in self.tables]
            if self.static_names:  # the prior that keeps an unobserved static value at its Coulomb value
                parts.append(np.array([(plant.value(n) - plant.value(n.replace("static", "coulomb")))
                                       / STATIC_PRIOR_NM for n in self.static_names]))
        return np.concatenate(parts) if parts else np.zeros(0)

    def weigh_recordings(self, x: np.ndarray) -> None:
        """Fix each recording's weight: one over its uncertainty times the square root of its
        residuals' autocorrelation time at ``x`` (one per joint, their mean)."""
        sims = self.simulated(x)
        for i, (s, src) in enumerate(zip(sims, self.sources)):
            d = s - src.recording.motor_rad
            tau = float(np.mean([autocorrelation_time(d[:, k]) for k in range(d.shape[1])]))
            self.weights[i] = 1.0 / (src.sigma_rad * math.sqrt(tau))

    def effective_count(self) -> float:
        """The number of independent residuals: each recording's samples over its autocorrelation
        time, and every table number."""
        n = sum((src.sigma_rad * w) ** 2 * src.recording.motor_rad.size
                for src, w in zip(self.sources, self.weights))
        return n + sum(len(t.numbers()) for t in self.tables) + len(self.static_names)

    def jacobian(self, x: np.ndarray, columns: Sequence[int] | None = None) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        base_plots = self._runs(x)
        r0 = self.residual(x, base_plots)
        cols = range(len(x)) if columns is None else columns
        J = np.zeros((r0.size, len(x)))
        shifted = []
        for i in cols:
            xi = x.copy()
            h = self.steps[i] if xi[i] + self.steps[i] <= self.highs[i] else -self.steps[i]
            xi[i] += h
            shifted.append((i, xi, h))
        needs_run = [(i, xi, h) for i, xi, h in shifted if self._needs_run(i) and self.sources]
        batch = [run for _, xi, _ in needs_run for run in self._lab_runs(xi)]
        results = self.runner.run_all(batch) if batch else []
        per = len(self.sources)
        for k, (i, xi, h) in enumerate(needs_run):
            J[:, i] = (self.residual(xi, results[k * per:(k + 1) * per]) - r0) / h
        for i, xi, h in shifted:
            if not self._needs_run(i) or not self.sources:
                J[:, i] = (self.residual(xi, base_plots) - r0) / h
        return J

    def _lab_runs(self, x: np.ndarray) -> list[IdentifyRun]:
        plant, terms = self.split(x)
        return [IdentifyRun(src.config, plant, rest, n)
                for src, (_, _, rest), n in zip(self.sources, terms, self.lengths)]

    def _needs_run(self, i: int) -> bool:
        if i < self.n_plant:
            return True
        return (i - self.n_plant) % self.per_source() >= 2  # the resting pose changes the run


def _rms(sims: Sequence[np.ndarray], sources: Sequence[Source]) -> tuple[list[np.ndarray], list[np.ndarray]]:
    rms, mx = [], []
    for s, src in zip(sims, sources):
        d = s - src.recording.motor_rad
        rms.append(np.sqrt(np.mean(d * d, axis=0)))
        mx.append(np.max(np.abs(d), axis=0))
    return rms, mx


def autocorrelation_time(residual: np.ndarray) -> float:
    """Integrated autocorrelation time (samples) of one residual series: ``1 + 2 sum rho_k`` up to
    the first negative ``rho_k``; 1 for white noise.

    >>> rng = np.random.default_rng(1)
    >>> round(autocorrelation_time(rng.normal(size=20000)))
    1
    >>> smooth = np.convolve(rng.normal(size=20000), np.ones(20) / 20, mode="same")
    >>> 15 < autocorrelation_time(smooth) < 25
    True
    """
    r = residual - residual.mean()
    n = len(r)
    if n < 4 or not np.any(r):
        return 1.0
    spectrum = np.fft.rfft(r, 2 * n)
    acf = np.fft.irfft(spectrum * np.conj(spectrum))[:n]
    acf /= acf[0]
    tau = 1.0
    for k in range(1, n // 2):
        if acf[k] < 0:
            break
        tau += 2 * acf[k]
    return float(tau)


def compare(sources: Sequence[Source], plant: PlantParams | None = None, *, jobs: int = 1,
            tables: Sequence[TableSource] = ()) -> FitResult:
    """``plant`` (default: crslab's arm) against ``sources`` and ``tables`` as they stand: each
    recording placed and aligned (phase and drift fitted), nothing of the plant changed.
    ``rms_after`` is ``rms_before``."""
    return fit(sources, names=(), start=plant, jobs=jobs, tables=tables)


def fit(sources: Sequence[Source], *, names: Sequence[str] = DEFAULT_FIT, start: PlantParams | None = None,
        fit_rest: bool = False, jobs: int = 1, max_iterations: int = 30, tables: Sequence[TableSource] = (),
        on_progress: Callable[[int, int, float | None], None] | None = None) -> FitResult:
    """Fit ``names`` (values or groups) of the plant, starting from ``start`` (default: the
    defaults), to the recordings ``sources`` and the friction ``tables`` together.
    ``on_progress(runs, estimated_total, rms)`` is called after every simulated run. No names:
    only the alignment (see :func:`compare`)."""
    # imported here, not with the module: every crslab command reads this module's names for its
    # help, and scipy's import would add more than half a second to each
    from scipy.optimize import least_squares

    start = PlantParams.defaults() if start is None else start
    if not sources and not tables:
        raise FitError("nothing to fit to: give a recording or a friction table")
    joints = {j for s in sources for j in s.recording.joints} | {j for t in tables for j in t.table.rows}
    fitted_names = names_to_fit(names, joints) if names else []
    if not sources:
        fitted_names = what_tables_tell(fitted_names)
    check_recordings([s.recording for s in sources])
    state = {"rms": None}
    per_iteration = (len(fitted_names) + 1) * len(sources)
    total = [len(sources) * 2 + per_iteration * (max_iterations + 1)]

    def progressed() -> None:
        if on_progress is not None:
            on_progress(runner.count, max(total[0], runner.count), state["rms"])

    with Runner(jobs, on_run=progressed) as runner:
        problem = Problem(sources, fitted_names, start, runner, fit_rest=fit_rest, tables=tables)
        problem.place()
        x0 = np.array(problem.x0, dtype=float)
        lows, highs, steps = map(np.array, (problem.lows, problem.highs, problem.steps))
        # the alignment alone first: the residual "before" is the starting plant at its best
        nuisance = list(range(problem.n_plant, len(x0)))
        cheap = [i for i in nuisance if not problem._needs_run(i)]
        if cheap:
            def nuisance_fun(z: np.ndarray) -> np.ndarray:
                x = x0.copy()
                x[cheap] = z
                return problem.residual(x)

            def nuisance_jac(z: np.ndarray) -> np.ndarray:
                x = x0.copy()
                x[cheap] = z
                return problem.jacobian(x, cheap)[:, cheap]

            pre = least_squares(nuisance_fun, x0[cheap], jac=nuisance_jac, bounds=(lows[cheap], highs[cheap]),
                                x_scale=steps[cheap], max_nfev=20)
            x0[cheap] = pre.x
        problem.weigh_recordings(x0)
        sim_before = problem.simulated(x0) if sources else []
        rms_before, _ = _rms(sim_before, sources)
        plant_before, _ = problem.split(x0)
        if sources:
            state["rms"] = float(np.sqrt(np.mean(np.concatenate([r ** 2 for r in rms_before]))))

        def fun(x: np.ndarray) -> np.ndarray:
            r = problem.residual(x)
            if sources:
                sims = problem.simulated(x)
                state["rms"] = float(np.sqrt(np.mean(np.concatenate(
                    [((s - src.recording.motor_rad) ** 2).ravel() for s, src in zip(sims, sources)]))))
            return r

        if fitted_names or fit_rest:
            result = least_squares(fun, x0, jac=problem.jacobian, bounds=(lows, highs), x_scale=steps,
                                   max_nfev=max_iterations, method="trf", xtol=XTOL, ftol=FTOL)
            x, jac, residual, message = result.x, result.jac, result.fun, str(result.message)
        else:
            x, message = x0, "alignment only"
            jac, residual = problem.jacobian(x), problem.residual(x)
        sim_after = problem.simulated(x) if sources else []
        rms_after, max_after = _rms(sim_after, sources)
        chi2 = float(residual @ residual) / max(problem.effective_count() - len(x), 1.0)
        sigma = _sigmas(jac, chi2)
        plant, terms = problem.split(x)
        runs = runner.count
    values, nuisance_values = [], []
    labels = list(fitted_names)
    for i in range(len(sources)):
        tag = f"recording{i + 1}" if len(sources) > 1 else "recording"
        labels += [f"{tag}.phase_ms", f"{tag}.drift"] + ([f"{tag}.rest2_rad", f"{tag}.rest3_rad"]
                                                         if fit_rest else [])
    for i, label in enumerate(labels):
        at_bound = bool(np.isclose(x[i], lows[i], atol=1e-9) or np.isclose(x[i], highs[i], atol=1e-9))
        item = Fitted(label, float(x0[i] if i >= problem.n_plant else problem.x0[i]), float(x[i]),
                      float(sigma[i]), at_bound)
        (values if i < problem.n_plant else nuisance_values).append(item)
    table_results = [TableResult(t, t.predicted(plant_before), t.predicted(plant)) for t in tables]
    return FitResult(plant=plant, start_plant=start, values=values, nuisance=nuisance_values,
                     alignments=problem.alignments, rms_before=rms_before, rms_after=rms_after,
                     max_after=max_after, sim_before=sim_before, sim_after=sim_after,
                     rests=[t[2] for t in terms], runs=runs, message=message, tables=table_results,
                     chi2_reduced=chi2)


def _sigmas(jac: np.ndarray, chi2_reduced: float) -> np.ndarray:
    """One standard deviation per fitted value (see the module's docstring)."""
    p = jac.shape[1]
    try:
        cov = np.linalg.pinv(jac.T @ jac) * max(1.0, chi2_reduced)
    except np.linalg.LinAlgError:
        return np.full(p, math.inf)
    return np.sqrt(np.clip(np.diag(cov), 0.0, None))


def what_tables_tell(names: Sequence[str]) -> list[str]:
    """Of ``names``, those friction tables alone can tell (:data:`TABLE_ONLY`). Raises
    :class:`FitError` when that is none of them."""
    told = [n for n in names if n.rstrip("0123456789") in TABLE_ONLY]
    if names and not told:
        raise FitError("a friction table tells only friction (and the motor gain): nothing else to fit")
    return told


def check_recordings(recordings: Sequence[Recording]) -> None:
    """Raise :class:`FitError` (naming the file) for a recording the fit cannot use: shorter than
    :data:`MIN_DURATION_S`, or one in which the arm hardly moves."""
    for rec in recordings:
        if rec.duration_s < MIN_DURATION_S:
            raise FitError(f"{rec.path}: {rec.duration_s:.2f} s long, shorter than a step response (the fit "
                           f"needs at least {MIN_DURATION_S:g} s)")
        if np.all(np.ptp(rec.motor_rad, axis=0) < 0.01):
            raise FitError(f"{rec.path}: the arm hardly moves in it (under 0.01 rad): nothing to fit")


def fitted_plant_values(result: FitResult) -> dict[str, float]:
    """The fitted plant values by name."""
    return {f.name: f.value for f in result.values}


def check_names(names: Sequence[str]) -> None:
    """Raise :class:`FitError` for a name that is neither a plant value nor a group."""
    try:
        names_to_fit(names, {1, 2, 3})
    except PlantParamsError as exc:
        raise FitError(str(exc)) from None


__all__ = ["DEFAULT_FIT", "GROUPS", "FitError", "FitResult", "Fitted", "Source", "TableResult", "TableSource",
           "autocorrelation_time",
           "check_names", "check_recordings", "compare", "fit", "fitted_plant_values", "names_to_fit"]
