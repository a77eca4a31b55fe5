"""Issue 14: what the sandbox costs.

- Sim throughput of the default lab with the sandbox against without it (target ratio >= 0.95),
  in ticks per CPU second of the worker (its user + system time, read from the kernel when it
  is reaped), over 100 000 ticks: on a shared 2-core machine other work moves wall-clock rates
  by tens of percent, CPU time hardly. The best wall-clock rates are printed too.
- The time the sandbox adds to starting a run (target < 0.1 s): entering it in a worker (closing
  descriptors, loading the trap, Landlock, the seccomp filter) and loading the lab through it,
  timed inside a forked worker, against loading the lab without it.
- The time it adds to compiling a lab (Landlock set up for the compiler).
"""

from __future__ import annotations

import dataclasses
import mmap
import os
import resource
import tempfile
import time
from pathlib import Path

from crslab.lab.build import DEFAULT_LAB, build_lab
from crslab.run.api import make_config
from crslab.run.assemble import started
from crslab.worker.board_ffi import native_board_ffi

REPEATS = 5
TICKS = 100_000
STARTS = 20
COMPILES = 4


def _children_cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def rates(config) -> tuple[float, float]:
    """(ticks per worker CPU second, ticks per wall second) of ``TICKS`` ticks at full speed."""
    cpu0 = _children_cpu_s()
    with started(config) as sim:
        t = time.perf_counter()
        result = sim.run(TICKS, speed=None)
        wall = time.perf_counter() - t
    assert result.ok, result.message
    return TICKS / (_children_cpu_s() - cpu0), TICKS / wall


def load_s(config) -> float:
    """Seconds a forked worker takes to enter the sandbox (if on) and load the lab."""
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # the worker's last steps before its first tick, as crslab.worker.main does them
        os.close(read)
        ffi = native_board_ffi()
        block = ffi.cast("crs_shared *", ffi.from_buffer(mmap.mmap(-1, ffi.sizeof("crs_shared"))))
        t = time.perf_counter()
        if config.sandboxed:
            from crslab.sandbox.run_sandbox import enter_run_sandbox

            box = enter_run_sandbox(block, config.build.shared_object, [write],
                                    trap_library=config.build.trap_library)
            with box.loading():
                ffi.dlopen(str(config.build.shared_object))
        else:
            ffi.dlopen(str(config.build.shared_object))
        os.write(write, repr(time.perf_counter() - t).encode())
        os._exit(0)
    os.close(write)
    text = os.read(read, 100)
    os.close(read)
    os.waitpid(pid, 0)
    return float(text)


def compile_s(sandboxed: bool, n: int, folder: Path) -> float:
    """Seconds to compile and link a lab that is not in the cache."""
    src = folder / f"lab_{int(sandboxed)}_{n}.c"
    src.write_text(DEFAULT_LAB.read_text() + f"\n/* build {n}, sandboxed {sandboxed} */\n")
    t = time.perf_counter()
    build_lab(src, sandboxed=sandboxed)
    return time.perf_counter() - t


def run() -> list[str]:
    on = make_config(sandbox=True, native=True)  # the run sandbox guards a native firmware
    off = dataclasses.replace(on, sandboxed=False)
    cpu, wall = {True: [], False: []}, {True: [], False: []}
    for i in range(REPEATS):  # interleaved, alternating which goes first
        for config in (on, off) if i % 2 == 0 else (off, on):
            c, w = rates(config)
            cpu[config.sandboxed].append(c)
            wall[config.sandboxed].append(w)
    loads = {True: [], False: []}
    for _ in range(STARTS):
        loads[True].append(load_s(on))
        loads[False].append(load_s(off))
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as labs:
        os.environ["CRSLAB_CACHE_DIR"] = cache
        try:
            compile_s(False, -1, Path(labs))  # the board's objects, once
            compiles = {True: [], False: []}
            for n in range(COMPILES):
                compiles[True].append(compile_s(True, n, Path(labs)))
                compiles[False].append(compile_s(False, n, Path(labs)))
        finally:
            del os.environ["CRSLAB_CACHE_DIR"]
    a, b = max(cpu[True]), max(cpu[False])
    l_on, l_off = min(loads[True]), min(loads[False])
    c_on, c_off = min(compiles[True]), min(compiles[False])
    return [
        f"sandboxed sim (Lab 1, {TICKS} ticks):   {a:,.0f} ticks per worker CPU second "
        f"(best wall clock {max(wall[True]):,.0f} ticks/s)",
        f"unsandboxed, same run:               {b:,.0f} ticks per worker CPU second "
        f"(best wall clock {max(wall[False]):,.0f} ticks/s)",
        f"ratio {a / b:.3f} (target >= 0.95)",
        f"entering the sandbox and loading the lab: {l_on * 1000:.1f} ms, loading it without: "
        f"{l_off * 1000:.1f} ms; the sandbox adds {(l_on - l_off) * 1000:.1f} ms to a start "
        "(target < 100 ms)",
        f"compiling a lab: {c_on * 1000:.0f} ms sandboxed, {c_off * 1000:.0f} ms without; "
        f"the sandbox adds {(c_on - c_off) * 1000:.0f} ms",
    ]
