"""Issues 3, 19 and 22: the simulator's throughput against physics-only baselines doing the same
physics, the lab as WebAssembly firmware against the same lab built natively, and the command as
a user runs it.

Everything runs crslab's default lab (Lab 1) on the default scenario (the tour, 25 000 ticks).

* **crslab, API**: ticks per second of ``BoardRun.run`` at ``--fast``, the worker already
  started (not timed): per tick the framework, ``lab()`` (its instructions counted, as ``crslab
  sim`` does), the hand, ``mj_step``; per chunk the pipe and the serial bytes. The lab runs as
  WebAssembly firmware (crslab's default). Best of ``2 * REPEATS``, each in a process of its own
  (``sim_rates.py``: a process's address-space layout moves crslab's rate by up to 15 %; the bare
  loop gets a new process, and so a new layout, every time too).
* **crslab, native**: the same with the lab built natively (``--native``: the firmware linked
  with the board, lab() timed by the thread's CPU clock), in the same processes, after the
  WebAssembly run. Target (issue 22): WebAssembly >= 0.95 of it, as the median of each process's
  ratio (the two share that process's layout; their best runs may come from different ones).
* **bare C loop** (``bare_mj_step.c``, see ``baselines.py``): ``mj_step`` of the same
  ``libmujoco`` on the same model, replaying the ``ctrl`` and ``qfrc_applied`` recorded from the
  same run tick by tick, nothing else per step; it must end in that run's state bit for bit.
  Best of ``REPEATS`` processes x 2 passes (the later passes warm): the strongest baseline.
  Targets: crslab >= 0.9 of it (issue 19), the WebAssembly firmware >= 0.88 (issue 22).
* **CPU time** of the same runs (Linux): the worker's time on a CPU during ``BoardRun.run``
  (``/proc/PID/schedstat``; the crslab process's share, about 1.5 ms a run, is left out) against
  the bare loop's process CPU time per pass. Wall time on a loaded machine (other programs, this
  machine's two cores) measures the scheduler as much as the code; CPU time does not. Best of
  each.
* **mujoco.rollout** of the same recorded controls and forces, one call from Python (it also
  stores every step's state), same final-state check. Best of ``REPEATS``. Target (issue 3):
  crslab >= 0.8 of it.
* **the command as a user runs it**: ``crslab sim --fast`` (the console script, stdin from
  /dev/null, stdout and stderr to files), timed from process start to exit: interpreter and
  import, lab build (cached), worker start-up, the run, shutdown. Best of ``REPEATS``.
* **start-up**: the same, with ``--no-startup-delay --duration 0.001`` (one ``lab()`` call):
  an upper bound on the time from command start to the first ``lab()`` call. Target (issue 3):
  < 1 s. crslab's modules are compiled to bytecode first, as pip's install does: in a checkout run
  with ``PYTHONDONTWRITEBYTECODE=1`` every command would compile them again (about 0.25 s of CPU).
* **many instances in one worker** (``instances.py``, issue 32): the worker's CPU per tick per
  instance with 1, 50 and 150 instances of the same lab on the tour in 250-tick chunks (serve's),
  from tick 4250 on (the hand moving the arm, lab() running: those ticks cost more than the
  tour's average, so the figure is not the bare loop's to compare with); best of 3 processes (a
  loaded machine moves a single figure by half).
* **paired ratios**: each repeat's crslab (best of its two processes) against the bare loop's
  passes of the same repeat (best of two), by CPU time and by wall time; the median over the
  repeats. On a loaded machine, a virtual one above all, even CPU time varies by up to 2x from one
  second to the next (a core shared, time stolen by the host): the best of each side may come from
  different moments, a pair comes from one.

The measurements are interleaved, so every side sees the same machine load.
"""

from __future__ import annotations

import compileall
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from baselines import build_bare_loop, record_run, rollout_run, run_bare_loop, same_physics

import crslab
from crslab.run.api import make_config

REPEATS = 5
CRSLAB = Path(sys.executable).with_name("crslab")  # the console script, as a user runs it


def rates_in_a_new_process() -> dict[str, tuple[float, float | None]]:
    """crslab's rates, WebAssembly then native, measured by ``sim_rates.py`` in a new process."""
    r = subprocess.run([sys.executable, str(Path(__file__).with_name("sim_rates.py"))], capture_output=True,
                       text=True)
    if r.returncode != 0:
        raise RuntimeError(f"sim_rates.py failed: {r.stderr.strip()}")
    return {k: tuple(v) for k, v in json.loads(r.stdout.splitlines()[-1]).items()}


def instances_in_a_new_process(counts: tuple[int, ...] = (1, 50, 150)) -> dict[int, float]:
    """The worker's CPU microseconds per tick per instance with each count of instances
    (``instances.py``), measured in a new process."""
    r = subprocess.run([sys.executable, str(Path(__file__).with_name("instances.py")), *map(str, counts)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"instances.py failed: {r.stderr.strip()}")
    return {int(k): v for k, v in json.loads(r.stdout.splitlines()[-1]).items()}


def command_s(args: list[str], out_dir: Path) -> float:
    """Wall time of ``crslab ARGS`` from process start to exit, stdout and stderr to files."""
    with open(out_dir / "stdout.txt", "wb") as out, open(out_dir / "stderr.txt", "wb") as err:
        t = time.perf_counter()
        code = subprocess.run([str(CRSLAB), *args], stdin=subprocess.DEVNULL, stdout=out,
                              stderr=err).returncode
        dt = time.perf_counter() - t
    if code != 0:
        raise RuntimeError(f"crslab {' '.join(args)} exited {code}: {(out_dir / 'stderr.txt').read_text()}")
    return dt


def run() -> list[str]:
    config = make_config()  # the default lab and the tour, as WebAssembly firmware
    native = make_config(native=True)
    ticks = config.scenario.end_tick
    # recorded in this process with the native firmware: a WebAssembly one would start wasmtime here,
    # in the process that then forks every worker (the physics is the same: same torques, same steps)
    rec = record_run(native, ticks)
    fast, first_call = ["sim", "--fast"], ["sim", "--fast", "--no-startup-delay", "--duration", "0.001"]
    with tempfile.TemporaryDirectory(prefix="crslab-bench-") as tmp:
        tmp = Path(tmp)
        exe = build_bare_loop(tmp)
        controls = rec.save(tmp / "controls.bin")
        compileall.compile_dir(Path(crslab.__file__).parent, quiet=1)  # as installed: bytecode kept
        command_s(fast, tmp)  # the lab build is cached before anything is timed
        sims, sims_cpu, bare, bare_cpu, rolls, commands, starts = [], [], [], [], [], [], []
        natives, natives_cpu = [], []
        paired, paired_wall = [], []  # per repeat: crslab's best of its processes / the bare loop's
        for _ in range(REPEATS):  # interleaved: every side sees the same machine load
            first = len(sims_cpu), len(sims)
            for _ in range(2):  # as many tries as the bare loop's passes, each in a new process
                rates = rates_in_a_new_process()
                wall, cpu = rates["wasm"]
                sims.append(wall)
                if cpu is not None:
                    sims_cpu.append(cpu)
                wall, cpu = rates["native"]
                natives.append(wall)
                if cpu is not None:
                    natives_cpu.append(cpu)
            loop = run_bare_loop(exe, controls, passes=2)
            same_physics(rec, loop.qpos_end, loop.qvel_end, "the bare C loop")
            assert loop.ticks == ticks
            bare += [ticks / s for s in loop.pass_s]
            bare_cpu += [ticks / s for s in loop.cpu_s]
            if len(sims_cpu) > first[0]:
                paired.append(max(sims_cpu[first[0]:]) / max(ticks / s for s in loop.cpu_s))
            paired_wall.append(max(sims[first[1]:]) / max(ticks / s for s in loop.pass_s))
            seconds, qpos, qvel = rollout_run(rec)
            same_physics(rec, qpos, qvel, "mujoco.rollout")
            rolls.append(ticks / seconds)
            commands.append(command_s(fast, tmp))
            starts.append(command_s(first_call, tmp))
    tries = [instances_in_a_new_process() for _ in range(3)]
    per_instance = {n: min(t[n] for t in tries) for n in tries[0]}
    sim, c_loop, roll, nat = max(sims), max(bare), max(rolls), max(natives)
    paired_cpu = (statistics.median(w / n for w, n in zip(sims_cpu, natives_cpu))
                  if natives_cpu and len(natives_cpu) == len(sims_cpu) else None)
    command, start = min(commands), min(starts)
    cpu_line = (f"  by CPU time (load-insensitive): crslab's worker {max(sims_cpu):,.0f} ticks/s, the bare C "
                f"loop {max(bare_cpu):,.0f} steps/s: ratio {max(sims_cpu) / max(bare_cpu):.2f}, best of "
                f"{2 * REPEATS} each" if sims_cpu else "  (CPU time: /proc/PID/schedstat not readable here)")
    return [
        f"same physics on both sides: Lab 1 on the tour, {ticks} ticks; the replays of the run's recorded "
        f"ctrl and qfrc_applied end in its state bit for bit (max |qfrc_applied| "
        f"{np.abs(rec.qfrc_applied).max():.1f} N.m)",
        f"crslab BoardRun.run --fast (API, worker started; framework + lab() + hand + mj_step + pipe), "
        f"lab as WebAssembly firmware, best of {2 * REPEATS}: {sim:,.0f} ticks/s",
        f"the same with the lab built natively (--native), interleaved, best of {2 * REPEATS}: {nat:,.0f} "
        f"ticks/s",
        f"  ratio WebAssembly / native, the median of each process's (one layout each), wall time: "
        f"{statistics.median(w / n for w, n in zip(sims, natives)):.2f}"
        + (f"; by the worker's CPU time: {paired_cpu:.2f}" if paired_cpu is not None else "")
        + " (target >= 0.95, issue 22)",
        f"bare C loop (copy ctrl, qfrc_applied; mj_step; same libmujoco), best of {2 * REPEATS} passes: "
        f"{c_loop:,.0f} steps/s",
        f"  ratio crslab API (WebAssembly) / bare C loop, wall time: {sim / c_loop:.2f} (target >= 0.9, "
        f"issue 19; >= 0.88, issue 22); native / bare C loop: {nat / c_loop:.2f}",
        cpu_line,
        f"  absolute, by CPU time: crslab's worker {1e6 / max(sims_cpu):.2f} us per tick, the bare C loop "
        f"{1e6 / max(bare_cpu):.2f} us per mj_step" if sims_cpu else "  (CPU time not readable here)",
        "many instances in one worker (Lab 1 on the tour from tick 4250, 250-tick chunks, serve's; no scope "
        "rows), the worker's CPU per tick per instance, best of 3: "
        + ", ".join(f"N={n}: {us:.2f} us" for n, us in per_instance.items()),
        f"  paired, each repeat's crslab against the bare loop's passes of the same repeat, the median of "
        f"{REPEATS}: by CPU time "
        + (f"{statistics.median(paired):.2f}" if paired else "(not readable here)")
        + f", by wall time {statistics.median(paired_wall):.2f} (each: "
        + " ".join(f"{r:.2f}" for r in paired) + ")",
        f"mujoco.rollout of the same controls and forces (one call, stores each state), best of {REPEATS}: "
        f"{roll:,.0f} steps/s",
        f"  ratio crslab API / mujoco.rollout: {sim / roll:.2f} (target >= 0.8, issue 3)",
        f"`crslab sim --fast` as a user runs it (process start to exit, stdout to a file), "
        f"best of {REPEATS}: {command:.2f} s for the {ticks / 1000:g} s tour = "
        f"{ticks / command:,.0f} ticks/s, {ticks / command / c_loop:.2f} of the bare C loop (no target)",
        f"`crslab sim --fast --no-startup-delay --duration 0.001` process start to exit (bounds "
        f"command start to first lab() call; cached build), best of {REPEATS}: {start:.2f} s "
        f"(target < 1 s, issue 3)",
    ]


if __name__ == "__main__":
    print("\n".join(run()))
