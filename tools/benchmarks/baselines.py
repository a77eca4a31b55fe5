"""The physics-only baselines crslab's simulator is measured against, doing the same physics.

A crslab run is recorded tick by tick in this process with crslab's own worker code
(:func:`record_run`): for every tick, the controls (``ctrl``, what the framework sent the
motors) and applied joint forces (``qfrc_applied``, the hand) that went into that tick's
``mj_step``. Two baselines replay them on the same model from the same initial state:

* the bare C loop (``bare_mj_step.c``, built here against the headers and the ``libmujoco`` of
  the installed ``mujoco`` package, the library crslab's worker calls): copy a tick's controls
  and forces into ``mjData``, ``mj_step``, nothing else;
* ``mujoco.rollout`` with ``control_spec = CTRL | QFRC_APPLIED``: MuJoCo's own open-loop
  stepping from Python, no Python per step (it also stores the state after every step).

All three step without MuJoCo's stage timers (``mjcb_time`` cleared, as crslab's worker does:
:mod:`crslab.plant.mujoco_c`), so none pays for profiling the others skip.

Both must end in the recorded run's final state bit for bit, which shows they did its physics.
"""

from __future__ import annotations

import os
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
from mujoco import rollout

from crslab.plant.model import SCENE_XML, load_model
from crslab.plant.mujoco_c import stop_stage_timers
from crslab.run.inprocess import InProcessRun
from crslab.worker.config import RunConfig

HARNESS_C = Path(__file__).resolve().parent / "bare_mj_step.c"
PACED_C = Path(__file__).resolve().parent / "paced_mj_step.c"
MODEL_XML = SCENE_XML


@dataclass(frozen=True)
class Recording:
    """What went into each ``mj_step`` of a crslab run, and the state it ended in."""

    qpos0: np.ndarray         # (nq,) joint positions before the first tick (after mj_forward)
    ctrl: np.ndarray          # (ticks, nu) ctrl of each tick's step, command units
    qfrc_applied: np.ndarray  # (ticks, nv) qfrc_applied of each tick's step, N.m
    qpos_end: np.ndarray      # (nq,) after the last step
    qvel_end: np.ndarray      # (nv,)

    @property
    def ticks(self) -> int:
        return len(self.ctrl)

    def save(self, path: Path) -> Path:
        """Write the controls file ``bare_mj_step`` reads (little-endian doubles)."""
        rows = np.hstack([self.ctrl, self.qfrc_applied]).ravel()
        np.concatenate([self.qpos0, rows]).astype("<f8").tofile(path)
        return path


def record_run(config: RunConfig, ticks: int) -> Recording:
    """Run ``config`` for ``ticks`` ticks with crslab's worker in this process, one tick at a
    time, keeping each tick's ``ctrl`` and ``qfrc_applied`` (they are set just before its
    ``mj_step`` and stay in ``mjData`` after it). Chunking never changes a run, so this is the
    physics of ``crslab sim`` on the same config."""
    run = InProcessRun(config)
    data = run.worker.data
    qpos0 = data.qpos.copy()
    ctrl = np.empty((ticks, data.ctrl.size))
    qfrc = np.empty((ticks, data.qfrc_applied.size))
    for k in range(ticks):
        run.run(k + 1)
        ctrl[k] = data.ctrl
        qfrc[k] = data.qfrc_applied
    return Recording(qpos0, ctrl, qfrc, data.qpos.copy(), data.qvel.copy())


def mujoco_dir() -> Path:
    """The installed ``mujoco`` package: ``include/`` and ``libmujoco.so*``."""
    return Path(mujoco.__file__).resolve().parent


def build_bare_loop(out_dir: Path, cc: str | None = None, source: Path = HARNESS_C) -> Path:
    """Compile ``bare_mj_step.c`` (or ``source``: ``paced_mj_step.c``) against the installed
    package's MuJoCo; returns the program."""
    pkg = mujoco_dir()
    include = pkg / "include"
    libs = sorted(pkg.glob("libmujoco.so*"))
    if not (include / "mujoco" / "mujoco.h").is_file() or not libs:
        raise RuntimeError(f"the mujoco package at {pkg} ships no C headers or no libmujoco")
    exe = Path(out_dir) / source.stem
    cmd = [cc or os.environ.get("CC", "gcc"), "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror",
           f"-I{include}", str(source), str(libs[0]), f"-Wl,-rpath,{pkg}", "-lm", "-o", str(exe)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"building the bare mj_step loop failed:\n{' '.join(cmd)}\n{r.stderr}")
    return exe


@dataclass(frozen=True)
class BareRun:
    """What one ``bare_mj_step`` process measured."""

    pass_s: list[float]       # wall time of each pass's stepping loop
    ticks: int
    qpos_end: np.ndarray
    qvel_end: np.ndarray
    cpu_s: list[float]        # the process's CPU time during each pass's loop


def run_bare_loop(exe: Path, controls: Path, passes: int = 2, model_xml: Path = MODEL_XML,
                  cpu: int | None = None) -> BareRun:
    """Run the bare loop over a saved recording ``passes`` times in one process, on ``model_xml``
    (default: the arm's own scene; a world's scene for a run in that world), on core ``cpu`` only
    when given (None: wherever the system puts it)."""
    pin = None if cpu is None else (lambda: os.sched_setaffinity(0, {cpu}))
    r = subprocess.run([str(exe), str(model_xml), str(controls), str(passes)], capture_output=True,
                       text=True, check=False, preexec_fn=pin)
    if r.returncode != 0:
        raise RuntimeError(f"bare_mj_step failed: {r.stderr.strip()}")
    rows = [line.split() for line in r.stdout.splitlines()]
    times = [float(row[1]) for row in rows if row[0] == "pass"]
    ticks = {int(row[2]) for row in rows if row[0] == "pass"}
    cpu = [float(row[3]) for row in rows if row[0] == "pass"]
    vec = {row[0]: np.array([float(v) for v in row[1:]]) for row in rows if row[0] in ("qpos", "qvel")}
    return BareRun(times, ticks.pop(), vec["qpos"], vec["qvel"], cpu)


@dataclass(frozen=True)
class PacedRun:
    """What the ``paced_mj_step`` processes of :func:`run_paced_loops` measured together."""

    steps: int
    cpu_s: float
    qpos_first: list[np.ndarray]  # each process's first run's final qpos (it started at tick 0)

    @property
    def us_per_step(self) -> float:
        return self.cpu_s / self.steps * 1e6


def run_paced_loops(exe: Path, controls: Path, runs_by_cpu: dict[int, int], seconds: float,
                    model_xml: Path = MODEL_XML) -> PacedRun:
    """Run ``paced_mj_step`` at once on each core of ``runs_by_cpu`` (pinned there) with that many
    runs, for ``seconds``, paced as a run host paces a page's runs (its chunks' length at real
    time, its wake-ups' window)."""
    from crslab.run.pacing import PAGE_CHUNKS
    from crslab.serve.run_host import BATCH_S

    pace = [str(PAGE_CHUNKS.realtime_ticks), str(BATCH_S * 1000)]
    procs = [subprocess.Popen([str(exe), str(model_xml), str(controls), str(runs), str(seconds), *pace],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              preexec_fn=lambda cpu=cpu: os.sched_setaffinity(0, {cpu}))
             for cpu, runs in runs_by_cpu.items() if runs > 0]
    steps, cpu_s, qpos = 0, 0.0, []
    for p in procs:
        out, err = p.communicate()
        if p.returncode != 0:
            raise RuntimeError(f"paced_mj_step failed: {err.strip()}")
        rows = {line.split()[0]: line.split()[1:] for line in out.splitlines()}
        steps, cpu_s = steps + int(rows["paced"][0]), cpu_s + float(rows["paced"][1])
        qpos.append(np.array([float(v) for v in rows["qpos"]]))
    return PacedRun(steps, cpu_s, qpos)


def rollout_run(rec: Recording) -> tuple[float, np.ndarray, np.ndarray]:
    """(seconds, final qpos, final qvel) of one ``mujoco.rollout`` call over the recording."""
    model = load_model()
    data = mujoco.MjData(model)
    data.qpos[:] = rec.qpos0
    mujoco.mj_forward(model, data)
    full = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.empty(mujoco.mj_stateSize(model, full))
    mujoco.mj_getState(model, data, state0, full)
    spec = mujoco.mjtState.mjSTATE_CTRL | mujoco.mjtState.mjSTATE_QFRC_APPLIED  # in this order
    control = np.hstack([rec.ctrl, rec.qfrc_applied])[None]
    stop_stage_timers()  # as in crslab's worker and the bare C loop
    start = time.perf_counter()
    states, _ = rollout.rollout(model, data, state0[None], control, control_spec=int(spec))
    seconds = time.perf_counter() - start
    end = mujoco.MjData(model)
    mujoco.mj_setState(model, end, states[0, -1], full)
    return seconds, end.qpos.copy(), end.qvel.copy()


def same_physics(rec: Recording, qpos: np.ndarray, qvel: np.ndarray, who: str) -> None:
    """Fail unless a replay ended in the recorded run's final state, bit for bit."""
    if not (np.array_equal(qpos, rec.qpos_end) and np.array_equal(qvel, rec.qvel_end)):
        raise AssertionError(f"{who} did not do the recorded run's physics: it ended at qpos {qpos}, "
                             f"qvel {qvel}; the run at qpos {rec.qpos_end}, qvel {rec.qvel_end}")

