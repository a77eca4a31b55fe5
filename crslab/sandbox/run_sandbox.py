"""The sandbox a lab runs in: entered by the worker process once Python, numpy and MuJoCo are
loaded and the plant is built, and before the lab's shared object is loaded, so the lab's
constructors and static initializers already run inside it.

In order (each step needs the ones before; none can be undone):

1. the worker is checked to be one thread (Landlock binds the calling thread and what it
   starts; a forked worker is one thread), standard input becomes /dev/null, every inherited
   descriptor but the standard streams and the pipe to the crslab process is closed, core
   dumps are off (a crash writes no file), no file may grow past 64 MB, and the environment is
   emptied (a teaching assistant's tokens never reach a transcript): the variables, and the
   block the process started with (/proc/self/environ), which a ``--sanitize`` run keeps
   because UBSan reads its options there when it first reports;
2. the libraries the lab's shared object needs (libm, libmvec, the sanitizer runtimes) are
   loaded now, so that loading the lab later opens that one file and nothing else; that file
   is opened now too;
3. the SIGSYS handler (:mod:`crslab.sandbox.trap`) is armed;
4. Landlock: no file may be opened, created or removed (a ``--sanitize`` run may read
   /proc/self, the Python program, the lab's build and the system libraries, which its error
   reports need; the trap lets it open them once it has begun a report on standard error), no
   TCP bind or connect, no signal to a process outside the sandbox;
5. seccomp: the allow-list of :mod:`crslab.sandbox.syscalls`; the rest is trapped and ends the
   run with a diagnosis.

A debugger (issue 18) is the one process that may trace the lab: pass its process id as
``tracer_pid`` and the worker names it its tracer (``PR_SET_PTRACER``, for Yama's ptrace scope
1) before the sandbox closes. ptrace from *outside* is not refused by either wall: seccomp
filters the lab's own calls, and Landlock lets a less restricted process trace a more
restricted one; the lab itself can never call ptrace.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import resource
import struct
import sys
from collections.abc import Iterable, Iterator
from pathlib import Path

from crslab import os_support
from crslab.sandbox import landlock
from crslab.sandbox.landlock import READ, RUN
from crslab.sandbox.syscalls import path_argument_table, run_filter
from crslab.sandbox.trap import Trap

MAX_FILE_BYTES = 64 * 1024 * 1024
"""The largest file the worker may grow (its only file is a ``--sanitize`` run's report)."""
SANITIZER_READ_DIRS = ("/usr/lib", "/usr/lib64", "/lib", "/lib64", "/usr/libexec")
"""What a ``--sanitize`` run's error report may read besides /proc/self and the lab's build."""


class SandboxError(OSError):
    """The worker could not enter the sandbox."""


def needed_libraries(shared_object: Path) -> list[str]:
    """The ``DT_NEEDED`` entries (library names) of a 64-bit little-endian ELF shared object.

    >>> import sys
    >>> any(name.startswith("libc.so") for name in needed_libraries(Path(sys.executable).resolve()))
    True
    """
    data = Path(shared_object).read_bytes()
    if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
        return []
    phoff, = struct.unpack_from("<Q", data, 0x20)
    phentsize, phnum = struct.unpack_from("<HH", data, 0x36)
    loads, dynamic = [], None
    for i in range(phnum):
        p_type, _, p_offset, p_vaddr, _, p_filesz, _, _ = struct.unpack_from("<IIQQQQQQ", data,
                                                                             phoff + i * phentsize)
        if p_type == 1:  # PT_LOAD
            loads.append((p_vaddr, p_offset, p_filesz))
        elif p_type == 2:  # PT_DYNAMIC
            dynamic = (p_offset, p_filesz)
    if dynamic is None:
        return []
    needed, strtab = [], None
    for off in range(dynamic[0], dynamic[0] + dynamic[1], 16):
        tag, value = struct.unpack_from("<qQ", data, off)
        if tag == 0:  # DT_NULL
            break
        if tag == 1:  # DT_NEEDED
            needed.append(value)
        elif tag == 5:  # DT_STRTAB
            strtab = next((value - v + o for v, o, n in loads if v <= value < v + n), None)
    if strtab is None:
        return []
    return [data[strtab + n:data.index(b"\0", strtab + n)].decode() for n in needed]


def _empty_environment(keep_start_block: bool) -> None:
    os.environ.clear()  # unsetenv() each: getenv() and environ find nothing
    if keep_start_block:
        return
    with open("/proc/self/stat") as f:  # fields 50 and 51: where the starting environment lies
        fields = f.read().rpartition(")")[2].split()
    start, end = int(fields[47]), int(fields[48])
    if 0 < start < end:
        ctypes.memset(start, 0, end - start)


def _close_inherited(keep: Iterable[int]) -> None:
    keep = {0, 1, 2, *keep}
    for name in os.listdir("/proc/self/fd"):
        fd = int(name)
        if fd not in keep:
            with contextlib.suppress(OSError):
                os.close(fd)
    devnull = os.open(os.devnull, os.O_RDONLY)
    os.dup2(devnull, 0)
    os.close(devnull)


class RunSandbox:
    """The entered sandbox: use :meth:`loading` around the lab's ``dlopen``."""

    def __init__(self, trap: Trap, lab_fd: int) -> None:
        self.trap = trap
        self.lab_fd = lab_fd

    @contextlib.contextmanager
    def loading(self) -> Iterator[None]:
        """While the lab's shared object is loaded: the loader may open that one file."""
        self.trap.loading(True)
        try:
            yield
        finally:
            self.trap.loading(False)


def enter_run_sandbox(shared: object, shared_object: Path, keep_fds: Iterable[int] = (), *,
                      trap_library: Path | None, sanitizer: bool = False,
                      tracer_pid: int | None = None) -> RunSandbox:
    """Close this worker process around the lab it is about to load (see the module's text).

    ``shared`` is the ``crs_shared *`` block the trap records refusals in; ``keep_fds`` the
    descriptors the worker still needs (the pipe to the crslab process, a sanitizer's report);
    ``trap_library`` the SIGSYS handler built with the lab (``LabBuild.trap_library``).
    """
    threads = len(os.listdir("/proc/self/task"))
    if threads != 1:
        raise SandboxError(0, f"the worker has {threads} threads; the sandbox needs it to have one")
    shared_object = Path(shared_object).absolute()
    libs = needed_libraries(shared_object)
    keep = list(keep_fds)
    _close_inherited(keep)
    _empty_environment(keep_start_block=sanitizer)
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    fsize = resource.getrlimit(resource.RLIMIT_FSIZE)[1]
    cap = MAX_FILE_BYTES if fsize == resource.RLIM_INFINITY else min(fsize, MAX_FILE_BYTES)
    resource.setrlimit(resource.RLIMIT_FSIZE, (cap, cap))
    for lib in libs:
        try:
            ctypes.CDLL(lib)
        except OSError as exc:
            raise SandboxError(0, f"{shared_object.name} needs {lib}, which cannot be loaded: "
                               f"{exc}") from None
    if trap_library is None:
        raise SandboxError(0, f"{shared_object.name} was built without the sandbox's trap")
    lab_fd = os.open(shared_object, os.O_RDONLY | os.O_CLOEXEC)
    try:
        trap = Trap(trap_library)
        trap.arm(shared, str(shared_object), lab_fd, path_argument_table(trap.table_size),
                 report_fd=2 if sanitizer else -1)
        if tracer_pid is not None:
            os_support.allow_tracer(tracer_pid)
        syscall_filter = run_filter(os.getpid(), sanitizer=sanitizer)
        try:
            rules = landlock.Ruleset()
            if sanitizer:
                for name in ("maps", "cmdline", "environ"):
                    rules.allow(f"/proc/{os.getpid()}/{name}", READ)
                rules.allow(shared_object.parent, READ)
                rules.allow(os.path.realpath(sys.executable), READ)  # /proc/self/exe, for symbols
                for d in SANITIZER_READ_DIRS:
                    rules.allow(d, RUN)
            rules.restrict_self()
            syscall_filter.load()
        finally:
            syscall_filter.release()
    except (OSError, landlock.LandlockError) as exc:
        os.close(lab_fd)
        raise SandboxError(0, f"the sandbox could not be entered: {exc}") from None
    return RunSandbox(trap, lab_fd)
