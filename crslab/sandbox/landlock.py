"""Landlock, the kernel's unprivileged access control: which files a process (and every process
it starts) may open, whether it may use TCP, and whether it may signal processes outside it.

Called through its three system calls with ctypes (no library or header needed). A ruleset
names the rights it *handles*; everything handled and not granted by a rule is refused (EACCES)
once :meth:`Ruleset.restrict_self` has run, for good. Rights a kernel does not know (an older
Landlock ABI) are simply not handled: :func:`abi_version` says which ABI this kernel has.

>>> ALL_FS_RIGHTS[1], ALL_FS_RIGHTS[3] == ALL_FS_RIGHTS[2] | TRUNCATE
(8191, True)
"""

from __future__ import annotations

import ctypes
import os
from functools import cache
from pathlib import Path

# system call numbers: the same on every architecture (added after the tables were unified)
_SYS_CREATE_RULESET, _SYS_ADD_RULE, _SYS_RESTRICT_SELF = 444, 445, 446
_CREATE_RULESET_VERSION = 1
_RULE_PATH_BENEATH = 1
PR_SET_NO_NEW_PRIVS = 38

# file-system rights (include/uapi/linux/landlock.h)
EXECUTE, WRITE_FILE, READ_FILE, READ_DIR = 1 << 0, 1 << 1, 1 << 2, 1 << 3
REMOVE_DIR, REMOVE_FILE, MAKE_CHAR, MAKE_DIR = 1 << 4, 1 << 5, 1 << 6, 1 << 7
MAKE_REG, MAKE_SOCK, MAKE_FIFO, MAKE_BLOCK, MAKE_SYM = 1 << 8, 1 << 9, 1 << 10, 1 << 11, 1 << 12
REFER, TRUNCATE, IOCTL_DEV = 1 << 13, 1 << 14, 1 << 15  # ABI 2, 3, 5
# network rights (ABI 4) and scopes (ABI 6)
BIND_TCP, CONNECT_TCP = 1 << 0, 1 << 1
SCOPE_ABSTRACT_UNIX_SOCKET, SCOPE_SIGNAL = 1 << 0, 1 << 1

ALL_FS_RIGHTS = {1: (1 << 13) - 1, 2: (1 << 14) - 1, 3: (1 << 15) - 1, 4: (1 << 15) - 1,
                 5: (1 << 16) - 1}
"""Every file-system right each Landlock ABI knows (later ABIs add none so far)."""

READ = READ_FILE | READ_DIR
RUN = READ | EXECUTE
WRITE_TREE = (WRITE_FILE | REMOVE_DIR | REMOVE_FILE | MAKE_DIR | MAKE_REG | MAKE_SYM | REFER
              | TRUNCATE)
FILE_ONLY = EXECUTE | WRITE_FILE | READ_FILE | TRUNCATE | IOCTL_DEV
"""The rights a rule on a single file (not a folder) may grant."""


class LandlockError(OSError):
    """Landlock is missing or refused a ruleset."""


class _RulesetAttr(ctypes.Structure):
    _fields_ = [("handled_access_fs", ctypes.c_uint64), ("handled_access_net", ctypes.c_uint64),
                ("scoped", ctypes.c_uint64)]


class _PathBeneathAttr(ctypes.Structure):
    _pack_ = 1
    _fields_ = [("allowed_access", ctypes.c_uint64), ("parent_fd", ctypes.c_int32)]


_libc = ctypes.CDLL(None, use_errno=True)
_syscall = _libc.syscall
_syscall.restype = ctypes.c_long
_prctl = _libc.prctl
_prctl.restype = ctypes.c_int
_prctl.argtypes = [ctypes.c_int, ctypes.c_ulong, ctypes.c_ulong, ctypes.c_ulong, ctypes.c_ulong]


def _check(result: int, what: str) -> int:
    if result < 0:
        err = ctypes.get_errno()
        raise LandlockError(err, f"{what}: {os.strerror(err)}")
    return result


@cache
def abi_version() -> int:
    """This kernel's Landlock ABI (1 = Linux 5.13 ... 7 = Linux 6.15); 0 when it has none (an
    old kernel, or Landlock not enabled at boot, or a container that filters the call)."""
    result = _syscall(ctypes.c_long(_SYS_CREATE_RULESET), None, ctypes.c_size_t(0),
                      ctypes.c_uint32(_CREATE_RULESET_VERSION))
    return max(0, int(result))


def fs_rights(abi: int) -> int:
    """Every file-system right Landlock ABI ``abi`` handles."""
    return ALL_FS_RIGHTS[min(abi, max(ALL_FS_RIGHTS))] if abi > 0 else 0


def set_no_new_privs() -> None:
    """Forbid gaining privileges through execve (set-user-id programs) from here on: required
    before an unprivileged process may restrict itself with Landlock or seccomp."""
    _check(_prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0), "prctl(PR_SET_NO_NEW_PRIVS)")


class Ruleset:
    """A Landlock ruleset: every file-system right (and, from ABI 4, TCP bind and connect;
    from ABI 6, signals and abstract UNIX sockets leaving the sandbox) is refused except what
    :meth:`allow` grants. Use :meth:`restrict_self` (or :meth:`restrict_fd` in a child)."""

    def __init__(self) -> None:
        self.abi = abi_version()
        if self.abi < 1:
            raise LandlockError(0, "this kernel has no Landlock")
        self.handled_fs = fs_rights(self.abi)
        attr = _RulesetAttr(self.handled_fs, BIND_TCP | CONNECT_TCP if self.abi >= 4 else 0,
                            SCOPE_ABSTRACT_UNIX_SOCKET | SCOPE_SIGNAL if self.abi >= 6 else 0)
        size = 24 if self.abi >= 6 else (16 if self.abi >= 4 else 8)
        self.fd = _check(_syscall(ctypes.c_long(_SYS_CREATE_RULESET), ctypes.byref(attr),
                                  ctypes.c_size_t(size), ctypes.c_uint32(0)), "landlock_create_ruleset")

    def allow(self, path: str | Path, rights: int) -> bool:
        """Grant ``rights`` on ``path`` and everything beneath it (a file gets only its file
        rights). A path that does not exist is skipped (returns False)."""
        try:
            fd = os.open(path, os.O_PATH | os.O_CLOEXEC)
        except OSError:
            return False
        try:
            if not os.path.isdir(path):
                rights &= FILE_ONLY
            attr = _PathBeneathAttr(rights & self.handled_fs, fd)
            _check(_syscall(ctypes.c_long(_SYS_ADD_RULE), ctypes.c_int(self.fd),
                            ctypes.c_int(_RULE_PATH_BENEATH), ctypes.byref(attr), ctypes.c_uint32(0)),
                   f"landlock_add_rule({path})")
        finally:
            os.close(fd)
        return True

    def restrict_self(self) -> None:
        """Apply the ruleset to this thread (and everything it starts from now on), for good."""
        set_no_new_privs()
        restrict_fd(self.fd)
        self.close()

    def close(self) -> None:
        """Release the ruleset's descriptor (a ruleset applied stays applied)."""
        if self.fd >= 0:
            os.close(self.fd)
            self.fd = -1


def restrict_fd(ruleset_fd: int) -> None:
    """``landlock_restrict_self`` on a ruleset descriptor: what a freshly forked child calls
    (after :func:`set_no_new_privs`) before it runs a program."""
    _check(_syscall(ctypes.c_long(_SYS_RESTRICT_SELF), ctypes.c_int(ruleset_fd), ctypes.c_uint32(0)),
           "landlock_restrict_self")
