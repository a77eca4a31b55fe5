"""wasmtime, which runs a lab's WebAssembly firmware inside the worker: where its C library is (the
PyPI package ``wasmtime`` ships it; the C core loads it by path, csrc/board/wasmtime_api.h), a
firmware's bytes and the digest that names its compiled code (shared by the worker's instances of
one firmware, and kept between runs), and loading the library ahead of forks.

>>> wasmtime_library().name
'_libwasmtime.so'
"""

from __future__ import annotations

import errno
import hashlib
import importlib.util
import os
import platform
import sys
from dataclasses import dataclass
from pathlib import Path

from crslab.cache import CacheError, cache_dir, private_file, read_sealed, seal_into_place, subfolder

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


COMPILED_FOLDER = "compiled"
"""The cache's folder of compiled firmware (the build checks it too: crslab.lab.build)."""


def compiled_module_path(wasm: bytes, memory_bytes: int, stack_bytes: int,
                         digest: str | None = None) -> Path | None:
    """Where wasmtime's compilation of the firmware ``wasm`` for a board with this memory and stack
    is kept between runs (``compiled/`` of crslab's build cache, checked now: this user's, not a
    link, :func:`crslab.cache.subfolder`), named by its :func:`module_digest` (``digest`` when
    already computed). None when the cache cannot be used (each run compiles the module then,
    about 0.06 s)."""
    try:
        folder = subfolder(cache_dir(), COMPILED_FOLDER)
    except (CacheError, OSError):
        return None
    return folder / f"{digest or module_digest(wasm, memory_bytes, stack_bytes)}.cwasm"


class WasmImageError(OSError):
    """A firmware that is not the one this user's build sealed (the message says so)."""


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
        """The firmware at ``path``, for a board with crslab's memory and stack limits: the bytes
        this user's build sealed there (read once, their seal checked on those very bytes), else
        :class:`WasmImageError`."""
        from crslab.lab.firmware import MEMORY_BYTES, NATIVE_STACK_BYTES

        wasm = read_sealed(path)
        if wasm is None:
            raise WasmImageError(errno.EACCES, f"{path.name} is not the firmware crslab built (its seal does "
                                               "not hold): build it again")
        digest = module_digest(wasm, MEMORY_BYTES, NATIVE_STACK_BYTES)
        return cls(wasm, digest, MEMORY_BYTES, NATIVE_STACK_BYTES)

    def compiled_path(self) -> Path | None:
        """Where its compiled module is kept between runs (:func:`compiled_module_path`)."""
        return compiled_module_path(self.wasm, self.memory_bytes, self.stack_bytes, self.digest)


class KeptModule:
    """wasmtime's compilation of one firmware in the cache (``path``, :func:`compiled_module_path`):
    :attr:`bytes`, the kept module as this user's board wrote it (read once, its seal checked on
    those very bytes; None when there is none or it is not sealed: the board compiles anew), and a
    private file (:attr:`fd`, 0600, made here) the board writes a new compilation to, which
    :meth:`keep` seals and renames into place. The board never opens a file of the cache.

    >>> import tempfile
    >>> kept = KeptModule(Path(tempfile.mkdtemp()) / "m.cwasm")
    >>> kept.bytes is None, os.write(kept.fd, b"machine code"), kept.keep(), KeptModule(kept.path).bytes
    (True, 12, True, b'machine code')
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        self.bytes = read_sealed(path)
        if self.bytes is None:  # a planted or damaged file is never loaded: removed
            path.unlink(missing_ok=True)
        self.fd, self._part = -1, None
        if self.bytes is None:
            try:
                self.fd, self._part = private_file(path.parent, path.name)
            except OSError:
                pass

    def discard(self) -> bool:
        """Close and remove the private file, keeping nothing; False."""
        if self.fd >= 0:
            os.close(self.fd)
            self.fd = -1
        if self._part is not None:
            self._part.unlink(missing_ok=True)
        return False

    def keep(self) -> bool:
        """Seal what the board wrote to :attr:`fd` (if anything) and rename it into place; the
        private file is closed and gone either way. Whether a module was kept."""
        if self.fd < 0 or self._part is None:
            return False
        try:
            size = os.fstat(self.fd).st_size
            data = os.pread(self.fd, size, 0) if size else b""
            if len(data) == size > 0:
                seal_into_place(self._part, self.path, data)
                return True
            return False
        except OSError:
            return False
        finally:
            os.close(self.fd)
            self.fd = -1
            self._part.unlink(missing_ok=True)


class NotCompiled(Exception):
    """wasmtime could not compile a firmware, or its compilation could not be kept."""


def compile_kept(image: WasmImage, kept: Path) -> None:
    """Have wasmtime compile ``image`` now, in this process (an engine of its own, made as a
    worker's is, freed before this returns: no worker, board or store), unless this user's board
    kept it at ``kept`` already (its :meth:`WasmImage.compiled_path`), and keep it there, sealed
    (:class:`KeptModule`: written to a private file, sealed, renamed into place): a worker that
    later loads the firmware only reads it. Raises :class:`NotCompiled` saying why it could not."""
    from crslab._bindings import compiled_board

    module = KeptModule(kept)
    if module.bytes is not None:
        return
    if module.fd < 0:
        raise NotCompiled(f"the compiled module cannot be kept in {kept.parent}")
    os.environ.update(ENGINE_ENVIRONMENT)
    c = compiled_board()
    library, wasm = c.text(str(wasmtime_library())), c.bytes_view(image.wasm)
    error = c.wasm_compile({
        "libwasmtime": library, "wasm": wasm, "wasm_len": len(image.wasm), "memory_bytes": image.memory_bytes,
        "stack_bytes": image.stack_bytes, "compiled": c.pointer("uint8_t *", 0), "compiled_fd": module.fd})
    kept_now = module.discard() if error else module.keep()
    if error:
        raise NotCompiled(error)
    if not kept_now:
        raise NotCompiled(f"the compiled module could not be kept at {kept}")


def preload() -> bool:
    """Load wasmtime's library into this process now, so that the processes it forks (a fork
    server's jobs and their lab workers) start with it loaded: about 0.1 s of CPU each saved.
    False when it cannot be loaded (a run then says why)."""
    from crslab._bindings import preload_wasmtime

    try:
        return preload_wasmtime(str(wasmtime_library()))
    except WasmtimeMissing:
        return False
