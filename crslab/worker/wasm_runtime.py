"""wasmtime, which runs a lab's WebAssembly firmware inside the worker: where its C library is (the
PyPI package ``wasmtime`` ships it; the C core loads it by path, csrc/board/wasmtime_api.h), a
firmware's bytes and the digest that names its compiled code (shared by the worker's instances of
one firmware, and kept between runs), and loading the library ahead of forks.

>>> wasmtime_library().name
'_libwasmtime.so'
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import platform
import sys
from dataclasses import dataclass
from pathlib import Path

from crslab.cache import CacheError, cache_dir, is_sealed, seal

ENGINE_ENVIRONMENT = {"WASMTIME_BACKTRACE_DETAILS": "1"}
"""What wasmtime reads from the environment when it makes an engine, as every engine of crslab's
has it (a trap's backtrace names the lab's file and line: the firmware carries its DWARF). It is part
of the engine's configuration: a module compiled by an engine without it is not loaded by one with
it (it is compiled again)."""


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


def module_digest(wasm: bytes, memory_bytes: int, stack_bytes: int) -> str:
    """The digest of wasmtime's compilation of the firmware ``wasm`` for a board with this memory
    and stack: everything it depends on (the module's bytes, wasmtime's library, the board's
    limits). It names the compiled module a worker's instances of this firmware share, and the file
    it is kept in between runs (:func:`compiled_module_path`)."""
    library = wasmtime_library()
    stat = library.stat()
    h = hashlib.sha256(wasm)
    h.update(f"{library}:{stat.st_size}:{stat.st_mtime_ns}:{memory_bytes}:{stack_bytes}".encode())
    return h.hexdigest()[:32]


def compiled_module_path(wasm: bytes, memory_bytes: int, stack_bytes: int,
                         digest: str | None = None) -> Path | None:
    """Where wasmtime's compilation of the firmware ``wasm`` for a board with this memory and stack
    is kept between runs (``compiled/`` of crslab's build cache; written by the board, see
    ``keep_compiled`` in csrc/board/firmware_wasm.c), named by its :func:`module_digest` (``digest``
    when already computed). None when the cache cannot be used (each run compiles the module then,
    about 0.06 s)."""
    try:
        folder = cache_dir() / "compiled"
        folder.mkdir(parents=True, exist_ok=True)
    except (CacheError, OSError):
        return None
    return folder / f"{digest or module_digest(wasm, memory_bytes, stack_bytes)}.cwasm"


@dataclass(frozen=True)
class WasmImage:
    """A firmware's bytes, read once, and its :func:`module_digest`, computed once: a worker
    reads and hashes each distinct firmware once, whatever number of instances run it."""

    wasm: bytes
    digest: str
    memory_bytes: int
    stack_bytes: int

    @classmethod
    def read(cls, path: Path) -> WasmImage:
        """The firmware at ``path``, for a board with crslab's memory and stack limits."""
        from crslab.lab.firmware import MEMORY_BYTES, NATIVE_STACK_BYTES

        wasm = path.read_bytes()
        digest = module_digest(wasm, MEMORY_BYTES, NATIVE_STACK_BYTES)
        return cls(wasm, digest, MEMORY_BYTES, NATIVE_STACK_BYTES)

    def compiled_path(self) -> Path | None:
        """Where its compiled module is kept between runs (:func:`compiled_module_path`)."""
        return compiled_module_path(self.wasm, self.memory_bytes, self.stack_bytes, self.digest)


def unsealed_compiled_removed(kept: Path) -> int | None:
    """Remove the compiled firmware at ``kept`` unless this user's board wrote it (its keyed digest,
    :func:`crslab.cache.is_sealed`): wasmtime loads such a file as machine code without checking it,
    so one planted under its name must never be loaded (the board compiles the module anew).
    Returns the sealed file's modification time (ns), or None when none is kept there now."""
    try:
        stamp = kept.stat().st_mtime_ns
    except OSError:
        return None
    if is_sealed(kept):
        return stamp
    kept.unlink(missing_ok=True)
    kept.with_name(kept.name + ".seal").unlink(missing_ok=True)
    return None


def seal_compiled(kept: Path, sealed_stamp: int | None = None) -> None:
    """Seal the compiled firmware the board has just written at ``kept`` (if it did: a file still
    with the modification time ``sealed_stamp`` it had when its seal was checked is the one sealed,
    and is not read again)."""
    try:
        stamp = kept.stat().st_mtime_ns
    except OSError:
        return
    try:
        if stamp != sealed_stamp and not is_sealed(kept):
            seal(kept)
    except (CacheError, OSError):
        kept.unlink(missing_ok=True)


class NotCompiled(Exception):
    """wasmtime could not compile a firmware, or its compilation could not be kept."""


def compile_kept(image: WasmImage, kept: Path) -> None:
    """Have wasmtime compile ``image`` now, in this process (an engine of its own, made as a
    worker's is, freed before this returns: no worker, board or store), keep it at ``kept`` (its
    :meth:`WasmImage.compiled_path`) and seal it: a worker that later loads the firmware only reads
    it. Raises :class:`NotCompiled` saying why it could not."""
    from crslab._bindings import compiled_board

    os.environ.update(ENGINE_ENVIRONMENT)
    c = compiled_board()
    library, path, wasm = c.text(str(wasmtime_library())), c.text(str(kept)), c.bytes_view(image.wasm)
    error = c.wasm_compile({
        "libwasmtime": library, "wasm": wasm, "wasm_len": len(image.wasm), "memory_bytes": image.memory_bytes,
        "stack_bytes": image.stack_bytes, "compiled_path": path})
    if error:
        raise NotCompiled(error)
    seal_compiled(kept)


def preload() -> bool:
    """Load wasmtime's library into this process now, so that the processes it forks (a fork
    server's jobs and their lab workers) start with it loaded: about 0.1 s of CPU each saved.
    False when it cannot be loaded (a run then says why)."""
    from crslab._bindings import preload_wasmtime

    try:
        return preload_wasmtime(str(wasmtime_library()))
    except WasmtimeMissing:
        return False
