"""What a lab tried, in words, from the record the sandbox's trap left (``crs_refusal`` in
csrc/board/board.h): "open /etc/hostname for reading", "start a new process", ...

>>> describe("openat", [0xFFFFFF9C, 0, os.O_WRONLY | os.O_CREAT, 0o644, 0, 0], "/tmp/x")
'open /tmp/x for writing'
>>> describe("socket", [2, 1, 0, 0, 0, 0], "")
'open a network socket (AF_INET)'
>>> describe("kill", [4242, 9, 0, 0, 0, 0], "", parent_pid=4242)
'send SIGKILL to process 4242 (crslab itself)'
>>> describe("mmap", [0, 1 << 30, 3, 0x22, 0, 0], "")
'allocate 1024 MB at once (a sandboxed lab may map at most 256 MB at a time)'
"""

from __future__ import annotations

import os
import signal

from crslab._bindings import text_of
from crslab.sandbox import seccomp
from crslab.sandbox.syscalls import MAX_MAPPING_BYTES

_FAMILIES = {1: "AF_UNIX", 2: "AF_INET", 10: "AF_INET6", 16: "AF_NETLINK", 17: "AF_PACKET"}
_PTRACE = {0: "PTRACE_TRACEME", 16: "PTRACE_ATTACH", 0x4206: "PTRACE_SEIZE"}
_PROCESS = ("fork", "vfork", "clone", "clone3")
_PROGRAM = ("execve", "execveat")
_OPEN_FLAGS_ARG = {"open": 1, "openat": 2, "openat2": -1, "creat": -1}
_REMOVE = ("unlink", "unlinkat", "rmdir")
_MAKE = ("mkdir", "mkdirat", "mknod", "mknodat", "symlink", "symlinkat", "link", "linkat")
_RENAME = ("rename", "renameat", "renameat2")
_LOOK = ("stat", "lstat", "newfstatat", "statx", "access", "faccessat", "faccessat2", "readlink",
         "readlinkat", "statfs", "getxattr", "listxattr")
_CHANGE = ("chmod", "fchmodat", "chown", "lchown", "fchownat", "truncate", "utimes", "utimensat",
           "setxattr")


def _signal_name(number: int) -> str:
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


def _open_phrase(syscall: str, args: list[int], path: str) -> str:
    flag_arg = _OPEN_FLAGS_ARG[syscall]
    flags = args[flag_arg] if flag_arg >= 0 else os.O_WRONLY | os.O_CREAT
    if syscall == "openat2":
        return f"open {path}"
    if syscall == "creat":
        return f"create {path}"
    mode = flags & os.O_ACCMODE
    how = {os.O_RDONLY: "reading", os.O_WRONLY: "writing", os.O_RDWR: "reading and writing"}.get(mode, "")
    return f"open {path} for {how}" if how else f"open {path}"


def describe(syscall: str, args: list[int], path: str, *, parent_pid: int | None = None) -> str:
    """The refused call ``syscall`` (a name) with its ``args`` and the ``path`` it named, as
    a phrase that completes "the lab tried to ...". ``parent_pid`` names the crslab process."""
    shown = path or "a file"
    if syscall in _OPEN_FLAGS_ARG:
        return _open_phrase(syscall, args, shown)
    if syscall in _PROGRAM:
        return f"run the program {shown}"
    if syscall in _PROCESS:
        return f"start a new process ({syscall}, as fork() and system() do)"
    if syscall in ("socket", "socketpair"):
        family = _FAMILIES.get(args[0], f"family {args[0]}")
        return f"open a network socket ({family})"
    if syscall in ("kill", "tgkill", "tkill"):
        target = args[0] & 0xFFFFFFFF
        target = target - (1 << 32) if target >= 1 << 31 else target
        sig = args[2] if syscall == "tgkill" else args[1]
        whom = f"process {target}"
        if target == 0:
            whom = "its whole process group"
        elif target == -1:
            whom = "every process it may signal"
        elif parent_pid is not None and target == parent_pid:
            whom += " (crslab itself)"
        return f"send {_signal_name(sig)} to {whom}"
    if syscall in ("prlimit64", "setrlimit"):
        target = args[0] & 0xFFFFFFFF if syscall == "prlimit64" else 0
        whom = "its own" if target == 0 else f"process {target}'s"
        if parent_pid is not None and target == parent_pid:
            whom += " (crslab itself)"
        return f"{'set' if syscall == 'setrlimit' or args[2] else 'read'} {whom} resource limits ({syscall})"
    if syscall == "fcntl":
        return f"make descriptor {args[0]} signal a process (fcntl command {args[1]}: F_SETOWN, O_ASYNC)"
    if syscall == "ptrace":
        return f"call ptrace ({_PTRACE.get(args[0], f'request {args[0]}')})"
    if syscall in ("mmap", "mremap"):
        size = args[1] if syscall == "mmap" else args[2]
        if size > MAX_MAPPING_BYTES:
            return (f"allocate {size / 2**20:.0f} MB at once (a sandboxed lab may map at most "
                    f"{MAX_MAPPING_BYTES // 2**20} MB at a time)")
    if syscall in _REMOVE:
        return f"remove {shown}"
    if syscall in _MAKE:
        return f"create {shown}"
    if syscall in _RENAME:
        return f"rename {shown}"
    if syscall in _LOOK:
        return f"look up {shown} ({syscall})"
    if syscall in _CHANGE:
        return f"change {shown} ({syscall})"
    if syscall == "rt_sigaction":
        return "replace the sandbox's SIGSYS handler"
    if syscall == "ioctl":
        return f"call ioctl on descriptor {args[0]}"
    if syscall in ("connect", "bind", "sendto", "sendmsg", "listen", "accept", "accept4"):
        return f"use a socket ({syscall})"
    return f"make the system call {syscall}"


def tried(record: object, *, parent_pid: int | None = None) -> str:
    """:func:`describe` of a ``crs_refusal`` record (the shared block's)."""
    nr, arch = int(record.syscall_nr), int(record.arch)  # type: ignore[attr-defined]
    args = [int(record.args[i]) for i in range(6)]  # type: ignore[attr-defined]
    path = text_of(record.text)  # type: ignore[attr-defined]
    if arch and arch != seccomp.native_arch():
        return f"make the {seccomp.name(nr, arch)} system call of another architecture (a 32-bit call)"
    return describe(seccomp.name(nr), args, path, parent_pid=parent_pid)
