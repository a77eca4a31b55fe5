"""Everything crslab does the Linux way, in one place, each item with what a macOS port needs.

crslab supports Linux, and Windows through WSL (which runs Linux). Every use of a Linux-only
facility goes through this module, so a port to macOS touches this file (and the one build-time
twin named under "Math libraries"), not the simulator.

>>> SHARED_OBJECT_FLAGS
['-shared', '-Wl,-Bsymbolic']
"""

from __future__ import annotations

import ctypes
import os
import platform
import resource
import shutil
import signal
import sys
import tempfile
from multiprocessing.context import BaseContext
from pathlib import Path

SUPPORTED_PLATFORMS = "Linux, and Windows through WSL"


def unsupported_platform(system: str | None = None) -> str | None:
    """Why this operating system is not supported, or None on Linux (WSL included).

    >>> unsupported_platform("linux") is None
    True
    >>> unsupported_platform("darwin")
    'darwin is not supported yet: crslab runs on Linux, and Windows through WSL'
    """
    system = sys.platform if system is None else system
    if system.startswith("linux"):
        return None
    return f"{system} is not supported yet: crslab runs on {SUPPORTED_PLATFORMS}"


# -- The worker dies with its parent ---------------------------------------------------------
# Linux: prctl(PR_SET_PDEATHSIG, SIGKILL) in the child; the kernel kills it when the parent dies,
# however the parent dies (kill -9 included).
# macOS: no prctl. The worker would watch its parent from a thread: kqueue with EVFILT_PROC and
# NOTE_EXIT on the parent's pid (select.kqueue), then os._exit.
PR_SET_PDEATHSIG = 1


PR_SET_NAME = 15


def name_process(name: str) -> None:
    """Give this process ``name`` (at most 15 bytes) where ``ps`` and ``/proc/PID/comm`` show it
    (Linux; elsewhere nothing)."""
    try:
        ctypes.CDLL(None).prctl(PR_SET_NAME, ctypes.c_char_p(name.encode()[:15]), 0, 0, 0)
    except (OSError, AttributeError):
        pass


def die_with_parent() -> None:
    """Ask the kernel to kill this process when its parent dies (best effort)."""
    try:
        ctypes.CDLL(None).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
    except (OSError, AttributeError):
        pass


# -- Lab globals named like libc functions -----------------------------------------------------
# Linux: the lab's shared object is linked -Wl,-Bsymbolic, so its references to a global named
# time, index or step bind to the lab's own definition, not libc's. (The load-time alternative,
# dlopen with RTLD_DEEPBIND, is not used: AddressSanitizer refuses it.)
# macOS: link with -dynamiclib instead; ld64 has no -Bsymbolic, and needs none: its two-level
# namespace binds an image's references to the image's own definitions. There is no RTLD_DEEPBIND.
SHARED_OBJECT_FLAGS = ["-shared", "-Wl,-Bsymbolic"]


# -- Math libraries ------------------------------------------------------------------------------
# Linux on x86-64: glibc's vector math (libmvec) next to libm, for loops the compiler vectorizes.
# csrc/cffi_build.py makes the same choice at build time (it cannot import crslab).
# macOS: libm is part of libSystem and there is no libmvec: no flags at all.
MATH_LIBS = ["-lm", "-lmvec"] if platform.machine() == "x86_64" and sys.platform.startswith("linux") \
    else ["-lm"]


# -- Shared memory between crslab and the worker ----------------------------------------------
# Linux: a memfd (memory with no name in any file system), mapped by both processes: the serial
# bytes never touch a disk, outlive a worker that crashes, and go with the last process that holds
# them, however it ends.
# macOS: no memfd_create; shm_open then shm_unlink at once does the same.
def anonymous_shared_file(name: str, size: int) -> int:
    """A descriptor of ``size`` bytes of shared memory named nowhere (``name`` is only a label)."""
    fd = os.memfd_create(name, os.MFD_CLOEXEC)
    os.ftruncate(fd, size)
    return fd


# -- MuJoCo's C library ----------------------------------------------------------------------------
# Linux: libmujoco.so.X inside the mujoco package; the C tick calls its mj_step directly.
# macOS: libmujoco.X.dylib (or mujoco.framework) inside the package.
def mujoco_library(package_dir: Path) -> Path | None:
    """The MuJoCo shared library the mujoco Python package loaded, or None."""
    libs = sorted(package_dir.glob("libmujoco.so*"))
    return libs[0] if libs else None


# -- The sanitizer runtime of --sanitize -------------------------------------------------------------
# Linux: the worker is a fresh interpreter with the ASan runtime in LD_PRELOAD.
# macOS: DYLD_INSERT_LIBRARIES with libclang_rt.asan_osx_dynamic.dylib; System Integrity
# Protection strips it for Apple's own /usr/bin/python3, so another Python is needed.
PRELOAD_ENV = "LD_PRELOAD"


# -- Memory limit of a lab's process ------------------------------------------------------------------
# Linux: RLIMIT_AS; an allocation past it fails and the lab crashes, as on an overfull board.
# macOS: RLIMIT_AS is not enforced; the crslab process would have to watch the worker's
# resident size (task_info) and kill it.
def limit_memory(size_bytes: int) -> None:
    """Cap this process's address space."""
    resource.setrlimit(resource.RLIMIT_AS, (size_bytes, size_bytes))


# -- How the worker starts -------------------------------------------------------------------------
# Linux: fork, fast, and the worker inherits everything already imported.
# macOS: fork is unsafe once Apple's frameworks are loaded (the viewer's window); "spawn", slower.
WORKER_START_METHOD = "fork"


# -- Processes started from a clean server -----------------------------------------------------------
# Linux: multiprocessing's fork server (a clean single-threaded process that imported `preload`
# once forks each job; the job may then fork a lab's worker safely). Elsewhere: spawn.
SOCKET_PATH_MAX = 107
"""The longest path of a Unix socket (sun_path, 108 bytes with its NUL)."""


def fork_server(preload: list[str]) -> BaseContext:
    """The context jobs start from: the fork server, importing ``preload`` once, else spawn.

    multiprocessing puts the fork server's socket in a folder of the temporary folder
    (``$TMPDIR/pymp-XXXXXXXX/listener-XXXXXXXX``): under a $TMPDIR too long for a socket's path that
    folder is made in /tmp instead (and removed at exit, as multiprocessing removes its own)."""
    import multiprocessing as mp
    from multiprocessing import process, util

    if "forkserver" not in mp.get_all_start_methods():  # pragma: no cover - every Linux has it
        return mp.get_context("spawn")
    config = process.current_process()._config  # where multiprocessing.util.get_temp_dir keeps it
    if not config.get("tempdir") and len(tempfile.gettempdir()) + 32 > SOCKET_PATH_MAX:
        folder = tempfile.mkdtemp(prefix="pymp-", dir="/tmp")
        util.Finalize(None, shutil.rmtree, args=(folder, True), exitpriority=-100)
        config["tempdir"] = folder
    ctx = mp.get_context("forkserver")
    ctx.set_forkserver_preload(preload)
    return ctx


# -- The --rrd writer process ------------------------------------------------------------------------
# Linux: forked at the command's start (crslab/sinks/rerun_writer.py), fed through a pipe whose
# buffer is raised to 1 MiB (F_SETPIPE_SZ) so a chunk of ticks goes down in one write.
# macOS: fork is safe that early (nothing but the standard library is loaded); there is no
# F_SETPIPE_SZ (pipes hold 64 KiB): the writer's reader thread drains them instead.
PIPE_BYTES = 1 << 20


def enlarge_pipe(fd: int) -> None:
    """Let the pipe whose end is ``fd`` hold up to :data:`PIPE_BYTES` (best effort)."""
    import fcntl

    try:
        fcntl.fcntl(fd, fcntl.F_SETPIPE_SZ, PIPE_BYTES)
    except (OSError, AttributeError):
        pass


# -- Pseudo-terminals (--pty) -------------------------------------------------------------------------
# Linux: os.openpty gives /dev/pts/N; with no terminal attached the master reports POLLHUP,
# which is how crslab drops bytes no one reads (crslab/sinks/serial_pty.py).
# macOS: openpty works (/dev/ttysNNN), but the "no terminal attached" test must be checked
# there and may need another way (the master's POLLHUP is not documented for BSD ptys).
def open_pty() -> tuple[int, int, str]:
    """A new pseudo-terminal: (master fd, slave fd, the slave's path)."""
    master, slave = os.openpty()
    return master, slave, os.ttyname(slave)


# -- Debugging a lab (crslab debug) --------------------------------------------------------------------
# Linux: gdb (or gdbserver) attaches to the worker with ptrace. Yama's ptrace scope 1 (Ubuntu's
# default) lets a process trace only its descendants, and the debugger is the worker's sibling:
# the worker names it with prctl(PR_SET_PTRACER, pid) before its sandbox closes (the relation
# ends when that process does). crslab sees the attach in /proc/<pid>/status (TracerPid).
# macOS: lldb or debugserver attach with task_for_pid, which needs the debugger signed with the
# debugging entitlement (or root) instead of a prctl; "attached" is P_TRACED in the worker's
# kinfo_proc (sysctl KERN_PROC_PID).
PR_SET_PTRACER = 0x59616D61
YAMA_SCOPE = Path("/proc/sys/kernel/yama/ptrace_scope")


def allow_tracer(pid: int) -> None:
    """Let process ``pid`` (and only it, besides this process's ancestors) trace this process.
    Without Yama the kernel already allows any process of the same user, and this does nothing."""
    try:
        ctypes.CDLL(None).prctl(PR_SET_PTRACER, pid, 0, 0, 0)
    except (OSError, AttributeError):
        pass


def tracer_of(pid: int) -> int | None:
    """The process tracing process ``pid`` (0: none), or None when ``pid`` is gone."""
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("TracerPid:"):
                    return int(line.split()[1])
    except (OSError, ValueError):
        return None
    return 0


def ptrace_restriction(scope_file: Path = YAMA_SCOPE) -> str | None:
    """What keeps a debugger from attaching on this machine, or None (Yama scope 0 or 1, or no
    Yama: crslab's PR_SET_PTRACER covers scope 1).

    >>> ptrace_restriction(Path("/nonexistent")) is None
    True
    """
    try:
        scope = int(scope_file.read_text())
    except (OSError, ValueError):
        return None
    if scope == 2:
        return "kernel.yama.ptrace_scope is 2: only root may attach a debugger"
    if scope >= 3:
        return "kernel.yama.ptrace_scope is 3: no process may attach a debugger until reboot"
    return None


# -- /proc ----------------------------------------------------------------------------------------------
# crslab reads nothing else from /proc: the worker's tick and phase travel through the shared
# block, so a crash or a hang is diagnosed without /proc/<pid>. Keep it that way: macOS has no /proc.


# -- The size of a loaded global ---------------------------------------------------------------
# Linux (glibc): dladdr1(address, &info, &sym, RTLD_DL_SYMENT) gives the ELF symbol the address
# belongs to, whose st_size is the object's size in bytes as the compiler laid it out. The host
# tools bound every host read and write to it, whatever the parse of the lab's source said.
# macOS: no dladdr1 and no sizes in Mach-O symbols; the bound would come from the distance to
# the next symbol of the image (dladdr's dli_saddr of the following address).
RTLD_DL_SYMENT = 1


class _DlInfo(ctypes.Structure):
    _fields_ = [("dli_fname", ctypes.c_char_p), ("dli_fbase", ctypes.c_void_p),
                ("dli_sname", ctypes.c_char_p), ("dli_saddr", ctypes.c_void_p)]


class _Elf64Sym(ctypes.Structure):
    _fields_ = [("st_name", ctypes.c_uint32), ("st_info", ctypes.c_ubyte), ("st_other", ctypes.c_ubyte),
                ("st_shndx", ctypes.c_uint16), ("st_value", ctypes.c_uint64), ("st_size", ctypes.c_uint64)]


def loaded_symbol_size(address: int) -> int | None:
    """Bytes of the loaded global that starts at ``address``, or None when the dynamic loader
    knows no symbol starting there (or this is not 64-bit glibc).

    >>> import ctypes; libc = ctypes.CDLL(None)
    >>> loaded_symbol_size(ctypes.cast(libc.printf, ctypes.c_void_p).value) > 0
    True
    """
    if ctypes.sizeof(ctypes.c_void_p) != 8:
        return None
    try:
        dladdr1 = ctypes.CDLL(None).dladdr1
    except AttributeError:
        return None
    dladdr1.argtypes = [ctypes.c_void_p, ctypes.POINTER(_DlInfo), ctypes.POINTER(ctypes.c_void_p),
                        ctypes.c_int]
    info, sym = _DlInfo(), ctypes.c_void_p()
    if not dladdr1(address, ctypes.byref(info), ctypes.byref(sym), RTLD_DL_SYMENT) or not sym.value:
        return None
    if info.dli_saddr != address:
        return None
    return int(_Elf64Sym.from_address(sym.value).st_size)
