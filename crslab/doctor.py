"""``crslab doctor``: check what a run needs, one line per item, each with its fix.

The items ``crslab sim`` cannot run without are *required* (the platform, Python, the WebAssembly
compiler (zig) and runtime (wasmtime), a lab that compiles to a firmware and runs on the board,
MuJoCo, a writable build cache); the others (a host C compiler, which ``--native``, ``--sanitize``
and ``crslab debug`` need; the sandbox, which ``crslab grade`` needs; a display for ``--viewer``,
the rerun viewer for ``--rerun``, pseudo-terminals for ``--pty``, gdb for ``crslab debug``) only
limit what crslab can do. The lab is built in the compile sandbox when this machine has it, afresh
in a temporary folder, so the check exercises the compiler even when the build cache holds the lab
already.

>>> Check("Python", True, "3.11.7").line()
'ok       Python: 3.11.7'
>>> Check("display", False, "no display", fix="use --rrd", required=False).line()
'missing  display: no display; fix: use --rrd'
"""

from __future__ import annotations

import os
import platform
import shutil
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

from crslab import os_support

MIN_PYTHON = (3, 11)


@dataclass(frozen=True)
class Check:
    """One item: its name, whether it is there, what was found (or what is wrong), the fix."""

    name: str
    ok: bool
    detail: str
    fix: str = ""
    required: bool = True
    skipped: bool = False

    def line(self) -> str:
        """The item as one line: ``ok``, ``FAILED`` (required), ``missing`` (optional) or
        ``skipped`` (an item it depends on failed)."""
        tag = "ok" if self.ok else "skipped" if self.skipped else "FAILED" if self.required else "missing"
        fix = f"; fix: {self.fix}" if not self.ok and self.fix else ""
        return f"{tag:<8} {self.name}: {self.detail}{fix}"


def _platform() -> Check:
    why = os_support.unsupported_platform()
    if why:
        return Check("platform", False, why, "use Linux, or on Windows run crslab inside WSL "
                     "(wsl --install, then pip install crslab there)")
    wsl = " (WSL)" if "microsoft" in platform.release().lower() else ""
    return Check("platform", True, f"Linux {platform.release()}{wsl}, {platform.machine()}")


def _python() -> Check:
    version = platform.python_version()
    if sys.version_info[:2] < MIN_PYTHON:
        return Check("Python", False, f"{version}; crslab needs {MIN_PYTHON[0]}.{MIN_PYTHON[1]} or newer",
                     "install a newer Python (e.g. sudo apt install python3.11) and a venv with it")
    return Check("Python", True, f"{version} ({sys.executable})")


def _compiler() -> Check:
    from crslab.lab.compiler import CompilerMissing, find_compiler

    name = "C compiler for --native, --sanitize and crslab debug"
    try:
        cc = find_compiler()
    except CompilerMissing as exc:
        message = str(exc)
        detail, _, fix = message.partition("; install one: ")
        return Check(name, False, detail, f"install one: {fix}" if fix else "", required=False)
    return Check(name, True, cc.describe(), required=False)


def _wasm() -> Check:
    from crslab.lab.zig import ZigMissing, zig_program, zig_version
    from crslab.worker.wasm_runtime import WasmtimeMissing, wasmtime_library

    fix = "pip install --force-reinstall crslab (it brings ziglang and wasmtime)"
    try:
        zig = zig_program()
        runtime = wasmtime_library()
    except (ZigMissing, WasmtimeMissing) as exc:
        return Check("WebAssembly compiler and runtime", False, str(exc), fix)
    from crslab.lab.firmware import is_zig_prepared
    from crslab.lab.zig import LIBC_ENV

    try:
        first = "" if is_zig_prepared() else "; its C library is built next, once per installation"
    except OSError:  # no cache to keep it in: the build cache's own line says so
        first = ""
    except RuntimeError as exc:  # a prepared C library that may not be linked: its line
        return Check("WebAssembly compiler and runtime", False, str(exc), f"remove it, or unset {LIBC_ENV}")
    return Check("WebAssembly compiler and runtime", True, f"zig {zig_version()} ({zig}){first}; wasmtime "
                 f"{metadata.version('wasmtime')} ({runtime.name})")


def _lab_build(have_wasm: bool, folder: Path, sandboxed: bool) -> tuple[Check, object]:
    if not have_wasm:
        return Check("lab build", False, "needs the WebAssembly compiler", "see above", skipped=True), None
    from crslab.lab.build import LabBuildError, build_lab
    from crslab.lab.firmware import prepare_zig

    try:  # once per installation, with its progress on stderr (then a first build takes seconds)
        prepare_zig()
    except RuntimeError as exc:
        return Check("lab build", False, str(exc),
                     "reinstall crslab (pip install --force-reinstall crslab)"), None
    start = time.monotonic()
    try:
        build = build_lab(cache=folder, sandboxed=sandboxed)
    except LabBuildError as exc:
        first = next((line for line in exc.diagnostics.splitlines() if "error" in line), "")
        return Check("lab build", False, f"{exc}{': ' + first.strip() if first else ''}",
                     "reinstall crslab (pip install --force-reinstall crslab)"), None
    took = time.monotonic() - start
    return Check("lab build", True, f"{build.source.name} compiles to a WebAssembly firmware with the "
                 f"framework's stand-ins ({took:.1f} s, built afresh)"), build


def _mujoco() -> Check:
    fix = "pip install --force-reinstall mujoco"
    try:
        import mujoco
        import numpy as np

        from crslab.plant.model import load_model, motor_to_qpos
        from crslab.plant.model_files import REST_MOTOR_RAD
        from crslab.plant.mujoco_c import mj_step_address

        model = load_model()
        data = mujoco.MjData(model)
        data.qpos[:3] = motor_to_qpos(REST_MOTOR_RAD)
        for _ in range(100):
            mujoco.mj_step(model, data)
        mj_step_address()  # the C tick calls MuJoCo's own mj_step
    except Exception as exc:  # noqa: BLE001 - whatever fails is the finding
        return Check("MuJoCo", False, f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}",
                     fix)
    if not (abs(data.time - 0.1) < 1e-9 and np.isfinite(data.qpos).all()):
        return Check("MuJoCo", False, f"stepping the arm went wrong (t = {data.time}, qpos = {data.qpos})",
                     fix)
    return Check("MuJoCo", True, f"{mujoco.__version__} loads the CRS arm and steps it (100 steps of 1 ms)")


def _simulation(build: object, sandboxed: bool) -> Check:
    if build is None:
        return Check("simulation", False, "needs the lab build", "see the lab build (above)", skipped=True)
    from crslab.run.assemble import run_kept
    from crslab.run.board_run import RunError
    from crslab.scenario.load import load_scenario
    from crslab.worker.config import RunConfig

    config = RunConfig(build=build, scenario=load_scenario("hands_off"), startup_ticks=0,  # type: ignore[arg-type]
                       sandboxed=sandboxed)
    try:
        result = run_kept(config, 600)
    except RunError as exc:
        return Check("simulation", False, str(exc), "run 'crslab sim' to see the whole message")
    lines = result.transcript.count(b"\n")
    if not result.ok or lines < 3:
        return Check("simulation", False, f"the lab's run ended {result.status} after {lines} lines "
                     f"{result.message}".rstrip(), "run 'crslab sim' to see the whole message")
    return Check("simulation", True, f"the lab's firmware ran 0.6 s on the board in a worker process and "
                 f"printed {lines} lines")


def _sandbox() -> Check:
    from crslab.sandbox import support

    found = support()
    if found.missing:
        return Check("sandbox", False, f"this machine lacks {'; '.join(found.missing)}: crslab sim runs labs "
                     "without it (with a warning) and crslab grade refuses to", "see docs/sandbox.md "
                     "('What it needs'); grade --no-sandbox runs a class without it", required=False)
    return Check("sandbox", True, found.summary().removeprefix("sandbox available: "), required=False)


def _cache() -> Check:
    from crslab.cache import CacheError, cache_dir

    try:
        folder = cache_dir()
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".doctor-"):
            pass
    except (CacheError, OSError) as exc:
        return Check("build cache", False, str(exc), "set CRSLAB_CACHE_DIR to a folder you can write")
    return Check("build cache", True, f"{folder} is writable")


def _display() -> Check:
    from crslab.scopes.display import missing_display

    why = missing_display()
    if why:
        return Check("display for --viewer", False, why, "run from a desktop session (on Windows 11, WSLg "
                     "gives WSL one); headless, save scopes with --rrd FILE or --csv FILE", required=False)
    shown = os.environ.get("WAYLAND_DISPLAY") or os.environ.get("DISPLAY")
    return Check("display for --viewer", True, f"{shown}", required=False)


def _rerun() -> Check:
    from crslab.scopes.rerun_stream import viewer_executable

    try:
        version = metadata.version("rerun-sdk")
    except metadata.PackageNotFoundError:
        return Check("rerun viewer", False, "rerun-sdk is not installed", "pip install rerun-sdk",
                     required=False)
    viewer = viewer_executable() or shutil.which("rerun")
    if viewer is None:
        return Check("rerun viewer", False, f"rerun-sdk {version} is installed but its viewer is not on PATH",
                     "pip install --force-reinstall rerun-sdk", required=False)
    return Check("rerun viewer", True, f"rerun-sdk {version}, viewer {viewer}", required=False)


def _pty() -> Check:
    try:
        master, slave, path = os_support.open_pty()
    except OSError as exc:
        return Check("pseudo-terminals for --pty", False, f"cannot open one ({exc.strerror})",
                     "mount devpts on /dev/pts (in a container: run it with a pty, e.g. docker run -t)",
                     required=False)
    os.close(slave)
    os.close(master)
    return Check("pseudo-terminals for --pty", True, f"opened {path}", required=False)


def _debugger() -> Check:
    from crslab.debug.programs import INSTALL, DebuggerMissing, debugger_for, gdb_version

    name = "debugger for crslab debug"
    try:
        gdb = debugger_for(console=True)
    except DebuggerMissing as exc:
        return Check(name, False, exc.what, exc.fix, required=False)
    restricted = os_support.ptrace_restriction()
    if restricted:
        return Check(name, False, restricted, "sudo sysctl kernel.yama.ptrace_scope=1 (scope 3 needs a "
                     "reboot first)", required=False)
    server = shutil.which("gdbserver")
    ide = f"gdbserver {server}" if server else \
        f"no gdbserver for --gdbserver (an IDE): {INSTALL['gdbserver']}"
    return Check(name, True, f"{gdb_version(gdb)} ({gdb}); {ide}", required=False)


def run_checks() -> Iterator[Check]:
    """Every check, in order, as it completes."""
    yield _platform()
    yield _python()
    wasm_check = _wasm()
    yield wasm_check
    yield _cache()
    sandbox_check = _sandbox()
    with tempfile.TemporaryDirectory(prefix="crslab-doctor-") as folder:
        build_check, build = _lab_build(wasm_check.ok, Path(folder), sandbox_check.ok)
        yield build_check
        yield _mujoco()
        yield _simulation(build, sandbox_check.ok)
    yield _compiler()
    yield sandbox_check
    yield _display()
    yield _rerun()
    yield _pty()
    yield _debugger()


def doctor(out: Callable[[str], None] = print) -> bool:
    """Run every check, printing one line each; True when everything ``crslab sim`` needs is here."""
    ok = True
    for check in run_checks():
        out(check.line())
        ok = ok and (check.ok or not check.required)
    return ok
