"""The SIGSYS handler of a sandboxed worker (csrc/sandbox/trap.c), built once per content like
the board's objects, and the calls that arm it.

A signal handler that must run at the very instruction a refused system call was made cannot be
Python (Python runs its handlers later, between bytecodes), hence this small C library, loaded
by the worker before the sandbox closes.
"""

from __future__ import annotations

import os
from functools import cache
from pathlib import Path

from cffi import FFI

from crslab.cache import CacheError, cache_dir
from crslab.cheaders import cdef_from_header
from crslab.lab.build import CSRC, SIM, LabBuildError, compiler, content_digest, run_compiler
from crslab.sim.board_ffi import board_ffi

TRAP_DIR = CSRC / "sandbox"
TRAP_SOURCE = TRAP_DIR / "trap.c"
TRAP_HEADER = TRAP_DIR / "trap.h"
TRAP_FLAGS = ["-std=c11", "-O2", "-fPIC", "-Wall", "-Wextra", "-Werror", "-shared"]


def helper_library() -> Path:
    """The built trap library (compiled on first use, then cached by content and compiler)."""
    cc = compiler()
    sources = [TRAP_SOURCE, TRAP_HEADER, SIM / "sim.h"]
    digest = content_digest([cc.identity.encode(), " ".join(TRAP_FLAGS).encode()]
                            + [p.read_bytes() for p in sources])
    try:
        out = cache_dir() / f"sandbox-{digest}" / "trap.so"
    except CacheError as exc:
        raise LabBuildError(str(exc)) from None
    if not out.exists():
        out.parent.mkdir(parents=True, exist_ok=True)
        tmp = out.with_suffix(f".{os.getpid()}.tmp")
        run_compiler([*cc.argv, *TRAP_FLAGS, "-I", str(SIM), str(TRAP_SOURCE), "-o", str(tmp)],
                     "crslab's sandbox trap")
        tmp.replace(out)
    return out


@cache
def trap_ffi() -> FFI:
    """The declarations of trap.h, on top of the shared block's (sim.h)."""
    ffi = FFI()
    ffi.include(board_ffi())
    ffi.cdef(cdef_from_header(TRAP_HEADER.read_text()))
    return ffi


class Trap:
    """The handler, loaded into this process: :meth:`arm` it before the seccomp filter is
    loaded, and turn :meth:`loading` on around the lab's ``dlopen``."""

    def __init__(self) -> None:
        try:
            path = helper_library()
        except LabBuildError as exc:
            raise OSError(f"the sandbox's trap could not be built: {exc}") from None
        self.ffi = trap_ffi()
        self.lib = self.ffi.dlopen(str(path))
        self._keep: list[object] = []

    def arm(self, shared: object, lab_path: str, lab_fd: int, path_argument: bytes,
            report_fd: int = -1) -> None:
        """Install the SIGSYS handler: refusals go to ``shared.refusal`` (a ``crs_shared *``);
        while loading, opens of ``lab_path`` get a duplicate of ``lab_fd``; once the sanitizer
        report file ``report_fd`` is not empty, opens for reading are carried out."""
        table = self.ffi.new("int8_t[]", len(path_argument))
        self.ffi.memmove(table, path_argument, len(path_argument))
        path = self.ffi.new("char[]", lab_path.encode())
        self._keep += [table, path]
        rc = self.lib.crs_trap_arm(self.ffi.cast("crs_shared *", shared), path, lab_fd, table, report_fd)
        if rc != 0:
            raise OSError(-rc, f"the sandbox's SIGSYS handler could not be installed: {os.strerror(-rc)}")

    def loading(self, on: bool) -> None:
        """Answer the loader's open of the lab's shared object (on) or refuse it like any (off)."""
        self.lib.crs_trap_loading(1 if on else 0)

    @property
    def table_size(self) -> int:
        """System calls the path-argument table covers."""
        return int(self.lib.CRS_TRAP_SYSCALLS)

    @property
    def exit_status(self) -> int:
        """The worker's exit status after a refused call."""
        return int(self.lib.CRS_TRAP_EXIT)
