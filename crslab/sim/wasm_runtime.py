"""wasmtime, which runs a lab's WebAssembly firmware inside the worker: where its C library is (the
PyPI package ``wasmtime`` ships it; crslab._core loads it by path, csrc/sim/wasmtime_api.h), and the
signal the crslab process sends the worker to interrupt a firmware call at its deadline.

>>> wasmtime_library().name
'_libwasmtime.so'
"""

from __future__ import annotations

import importlib.util
import platform
import signal
import sys
from pathlib import Path

INTERRUPT_SIGNAL = signal.SIGUSR1
"""Sent to the worker at a deadline: its handler (csrc/sim/firmware_wasm.c) bumps wasmtime's epoch,
and the firmware's running call traps at its next loop iteration or call."""


class WasmtimeMissing(FileNotFoundError):
    """The wasmtime package (a dependency of crslab) is not installed or lacks its library."""


def wasmtime_library() -> Path:
    """The path of the wasmtime C library of the installed ``wasmtime`` package."""
    spec = importlib.util.find_spec("wasmtime")
    if spec is None or not spec.submodule_search_locations:
        raise WasmtimeMissing("wasmtime is missing: reinstall crslab (it depends on the wasmtime package)")
    machine = {"AMD64": "x86_64", "arm64": "aarch64", "ARM64": "aarch64"}.get(platform.machine(),
                                                                              platform.machine())
    system = "linux" if sys.platform.startswith("linux") else sys.platform
    name = {"win32": "_wasmtime.dll", "darwin": "_libwasmtime.dylib"}.get(sys.platform, "_libwasmtime.so")
    path = Path(next(iter(spec.submodule_search_locations))) / f"{system}-{machine}" / name
    if not path.is_file():
        raise WasmtimeMissing(f"wasmtime's library is missing ({path}): reinstall the wasmtime package")
    return path
