"""The SIGSYS handler of a sandboxed worker (csrc/sandbox/trap.c), and the calls that arm it.

A signal handler that must run at the very instruction a refused system call was made cannot be
Python (Python runs its handlers later, between bytecodes), hence this small C library, built
with a native lab (:func:`crslab.lab.build.trap_library`, ``LabBuild.trap_library``) and loaded
by the worker before the sandbox closes.
"""

from __future__ import annotations

import os
from functools import cache
from pathlib import Path

from cffi import FFI

from crslab import resources
from crslab.cheaders import cdef_from_header


@cache
def trap_ffi() -> FFI:
    """The declarations of trap.h; the shared block (``crs_shared``, board.h) it writes refusals into
    is opaque here: the handler is C, and Python only hands it the block's address."""
    ffi = FFI()
    ffi.cdef("typedef struct crs_shared crs_shared;")
    ffi.cdef(cdef_from_header(resources.path("csrc", "sandbox", "trap.h").read_text()))
    return ffi


class Trap:
    """The handler, loaded into this process: :meth:`arm` it before the seccomp filter is
    loaded, and turn :meth:`loading` on around the lab's ``dlopen``."""

    def __init__(self, library: Path) -> None:
        self.ffi = trap_ffi()
        self.lib = self.ffi.dlopen(str(library))
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
        block = self.ffi.cast("crs_shared *", self.ffi.cast("uintptr_t", shared))
        rc = self.lib.crs_trap_arm(block, path, lab_fd, table, report_fd)
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
