"""The system calls a sandboxed run may make: an allow-list built from what the worker needs
once the lab is loaded (MuJoCo and numpy allocating, the pipe to the crslab process, clocks,
futexes, returning from signals), and nothing else. Every other call is trapped (SIGSYS) and
diagnosed; see csrc/sandbox/trap.c.

What is allowed is narrowed by its arguments where an argument decides the risk:

- memory: ``mmap`` and ``mremap`` of at most :data:`MAX_MAPPING_BYTES` at once (the board has
  68 KB of RAM: a lab asking for a gigabyte is diagnosed, not obeyed);
- signals: only to the worker itself (``raise``, ``abort``); the sandbox's own SIGSYS
  handler cannot be replaced, and SIGSYS cannot be blocked (the handler applies such a mask
  without it);
- file status: only of a descriptor already open (``fstat``; the C library's ``newfstatat`` with
  an empty path is answered by the trap), never of a path;
- descriptors: ``fcntl`` may read and set a descriptor's flags, never make it signal a process
  (``F_SETOWN``, ``O_ASYNC``: SIGIO to ``crslab grade``);
- terminals: ``ioctl`` only to ask whether a descriptor is one (``isatty``), never to type
  into it (``TIOCSTI``) or change it;
- resource limits: its own, read, never raised (``prlimit64`` of another process, the crslab
  process above all, is refused).

A ``--sanitize`` run is allowed what the sanitizer runtime needs besides (any mapping size,
reading its own /proc files and the lab's debug information, through the trap).

No call opens a file, a socket or a process; the worker has no descriptor but its standard
streams (input is /dev/null) and the pipe to the crslab process. Landlock refuses every file
and TCP access on its own as a second wall (:mod:`crslab.sandbox.run_sandbox`).
"""

from __future__ import annotations

import signal

from crslab.sandbox import seccomp
from crslab.sandbox.seccomp import ALLOW, TRAP, eq, le, masked_eq, ne

MAX_MAPPING_BYTES = 256 * 1024 * 1024
"""The most memory a single ``mmap``/``mremap`` may ask for in a sandboxed run."""

AT_EMPTY_PATH = 0x1000
TCGETS = 0x5401
F_DUPFD, F_GETFD, F_SETFD, F_GETFL, F_SETFL, F_DUPFD_CLOEXEC = 0, 1, 2, 3, 4, 1030
O_ASYNC = 0o20000
FCNTL_COMMANDS = (F_DUPFD, F_GETFD, F_SETFD, F_GETFL, F_DUPFD_CLOEXEC)
"""What ``fcntl`` may do besides ``F_SETFL`` without ``O_ASYNC``."""

# no argument decides anything: allowed as they are
_PLAIN = (
    # the pipe to the crslab process, the standard streams, the loader reading the lab
    "read", "write", "readv", "writev", "pread64", "close", "fstat", "lseek", "dup", "dup3",
    "poll", "ppoll", "select", "pselect6",
    # memory
    "brk", "munmap", "madvise", "mprotect", "membarrier",
    # time (normally answered in user space by the vDSO)
    "clock_gettime", "clock_getres", "gettimeofday", "time", "nanosleep", "clock_nanosleep",
    # signals and threads of this process
    "rt_sigreturn", "sigaltstack", "futex", "sched_yield", "getpid", "gettid",
    "getppid", "restart_syscall",
    # identity and accounting of this process
    "getuid", "geteuid", "getgid", "getegid", "getrusage", "getrandom",
    # ending
    "exit", "exit_group",
)

PATH_ARGUMENT = {
    "open": 0, "creat": 0, "openat": 1, "openat2": 1, "execve": 0, "execveat": 1, "stat": 0,
    "lstat": 0, "newfstatat": 1, "statx": 1, "access": 0, "faccessat": 1, "faccessat2": 1,
    "readlink": 0, "readlinkat": 1, "unlink": 0, "unlinkat": 1, "rmdir": 0, "mkdir": 0,
    "mkdirat": 1, "rename": 0, "renameat": 1, "renameat2": 1, "link": 0, "linkat": 1,
    "symlink": 1, "symlinkat": 2, "chmod": 0, "fchmodat": 1, "chown": 0, "lchown": 0,
    "fchownat": 1, "truncate": 0, "chdir": 0, "chroot": 0, "mknod": 0, "mknodat": 1,
    "utimes": 0, "utimensat": 1, "statfs": 0, "getxattr": 0, "setxattr": 0, "listxattr": 0,
    "inotify_add_watch": 1, "mount": 1, "umount2": 0, "swapon": 0, "uselib": 0,
}
"""Which argument of each file call is a path, so the diagnosis can name the file."""


def path_argument_table(size: int) -> bytes:
    """``PATH_ARGUMENT`` by native system-call number, -1 for calls without a path (int8 each)."""
    table = bytearray(b"\xff" * size)
    for name, arg in PATH_ARGUMENT.items():
        nr = seccomp.number(name)
        if 0 <= nr < size:
            table[nr] = arg
    return bytes(table)


def run_filter(worker_pid: int, *, sanitizer: bool = False) -> seccomp.Filter:
    """The filter a lab runs under: ``worker_pid`` is the worker's own process id (the only
    process it may signal). ``sanitizer`` widens it for the AddressSanitizer runtime, which
    reads /proc/self/maps and the lab's debug information when it reports (opened through the
    trap, Landlock still limiting what it can read) and maps its shadow memory in huge pieces."""
    f = seccomp.Filter(TRAP, keep_speculation=True)
    try:
        for name in _PLAIN:
            f.add(ALLOW, name)
        if sanitizer:
            f.add(ALLOW, "mmap")
            f.add(ALLOW, "mremap")
            f.add(ALLOW, "openat2")  # how the trap opens what a sanitizer's report reads
            for name in ("readlink", "readlinkat", "sched_getaffinity", "getrlimit", "prlimit64",
                         "newfstatat", "statx", "getdents64", "prctl", "arch_prctl", "uname"):
                f.add(ALLOW, name)
        else:
            f.add(ALLOW, "mmap", le(1, MAX_MAPPING_BYTES))
            f.add(ALLOW, "mremap", le(2, MAX_MAPPING_BYTES))
            f.add(ALLOW, "prlimit64", eq(0, 0), eq(2, 0))  # read its own limit, never set one
            f.add(ALLOW, "getrlimit")
        for command in FCNTL_COMMANDS:
            f.add(ALLOW, "fcntl", eq(1, command))
        f.add(ALLOW, "fcntl", eq(1, F_SETFL), masked_eq(2, O_ASYNC, 0))
        f.add(ALLOW, "ioctl", eq(1, TCGETS))  # isatty(): reads a terminal's settings, changes nothing
        f.add(ALLOW, "rt_sigaction", ne(0, signal.SIGSYS))
        # reading the signal mask or unblocking is allowed; a change that may block SIGSYS is
        # trapped and applied by the handler without SIGSYS (csrc/sandbox/trap.c)
        f.add(ALLOW, "rt_sigprocmask", eq(1, 0))
        f.add(ALLOW, "rt_sigprocmask", eq(0, signal.SIG_UNBLOCK))
        f.add(ALLOW, "kill", eq(0, worker_pid))
        f.add(ALLOW, "tgkill", eq(0, worker_pid))
        f.add(ALLOW, "tkill", eq(0, worker_pid))
    except BaseException:
        f.release()
        raise
    return f
