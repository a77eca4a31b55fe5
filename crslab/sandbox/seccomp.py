"""seccomp-bpf system-call filters, built with libseccomp (the library behind the seccomp
support of systemd, Docker, Flatpak, nsjail and isolate).

libseccomp's shared library (``libseccomp.so.2``, Debian's and Ubuntu's ``libseccomp2``, present
wherever systemd or apt is) is loaded through cffi in ABI mode: no headers, no compiler and no
Python binding package are needed (libseccomp's own Python binding is not on PyPI). The values
below are the kernel's and libseccomp's stable ABI.

>>> number("openat") > 0, name(number("openat"))
(True, 'openat')
>>> number("no_such_call")
-1
"""

from __future__ import annotations

import ctypes
import os
from dataclasses import dataclass
from functools import cache

from cffi import FFI

_CDEF = """
typedef void *scmp_filter_ctx;
typedef uint64_t scmp_datum_t;
struct scmp_arg_cmp { unsigned int arg; int op; scmp_datum_t datum_a; scmp_datum_t datum_b; };
struct scmp_version { unsigned int major; unsigned int minor; unsigned int micro; };
const struct scmp_version *seccomp_version(void);
scmp_filter_ctx seccomp_init(uint32_t def_action);
void seccomp_release(scmp_filter_ctx ctx);
int seccomp_attr_set(scmp_filter_ctx ctx, int attr, uint32_t value);
int seccomp_syscall_resolve_name(const char *name);
uint32_t seccomp_arch_native(void);
char *seccomp_syscall_resolve_num_arch(uint32_t arch_token, int num);
int seccomp_rule_add_array(scmp_filter_ctx ctx, uint32_t action, int syscall, unsigned int arg_cnt,
                           const struct scmp_arg_cmp *arg_array);
int seccomp_load(const scmp_filter_ctx ctx);
void free(void *);
"""

# actions (seccomp.h / linux/seccomp.h)
KILL_PROCESS = 0x80000000
TRAP = 0x00030000
ALLOW = 0x7FFF0000


def errno_action(err: int) -> int:
    """The action that fails the call with ``err`` instead of running it."""
    return 0x00050000 | (err & 0xFFFF)


# comparison operators of struct scmp_arg_cmp
_NE, _LT, _LE, _EQ, _GE, _GT, _MASKED_EQ = 1, 2, 3, 4, 5, 6, 7
# filter attributes
_ATTR_ACT_BADARCH, _ATTR_CTL_NNP, _ATTR_CTL_TSYNC, _ATTR_CTL_SSB = 2, 3, 4, 7
_ARCH_NATIVE = 0


class SeccompError(OSError):
    """libseccomp is missing or refused a filter."""


@dataclass(frozen=True)
class Cond:
    """A condition on one argument of a call: ``op`` compares argument ``arg`` with ``a``
    (for ``masked``: ``arg & a == b``)."""

    arg: int
    op: int
    a: int
    b: int = 0


def eq(arg: int, value: int) -> Cond:
    """Argument ``arg`` equals ``value``."""
    return Cond(arg, _EQ, value & 0xFFFFFFFFFFFFFFFF)


def ne(arg: int, value: int) -> Cond:
    """Argument ``arg`` differs from ``value``."""
    return Cond(arg, _NE, value & 0xFFFFFFFFFFFFFFFF)


def le(arg: int, value: int) -> Cond:
    """Argument ``arg`` (unsigned) is at most ``value``."""
    return Cond(arg, _LE, value)


def masked_eq(arg: int, mask: int, value: int) -> Cond:
    """``argument & mask == value``."""
    return Cond(arg, _MASKED_EQ, mask, value)


@cache
def _library() -> tuple[FFI, object]:
    ffi = FFI()
    ffi.cdef(_CDEF)
    try:
        lib = ffi.dlopen("libseccomp.so.2")
    except OSError:
        raise SeccompError(0, "libseccomp is not installed (Debian/Ubuntu: apt install libseccomp2)") \
            from None
    return ffi, lib


def version() -> tuple[int, int, int] | None:
    """libseccomp's version, or None when it cannot be loaded. Read through ctypes: every command's
    start asks (crslab/sandbox/support.py), and cffi's declarations would cost it cffi's C parser
    (pycparser: tens of milliseconds); the filters are built with cffi (:func:`_library`)."""
    try:
        lib = ctypes.CDLL("libseccomp.so.2")
    except OSError:
        return None
    lib.seccomp_version.restype = ctypes.POINTER(ctypes.c_uint * 3)  # struct scmp_version
    v = lib.seccomp_version().contents
    return (int(v[0]), int(v[1]), int(v[2]))


def number(syscall: str) -> int:
    """The native number of a system call by name (-1 when this architecture has none)."""
    ffi, lib = _library()
    nr = int(lib.seccomp_syscall_resolve_name(syscall.encode()))
    return nr if nr >= 0 else -1


def native_arch() -> int:
    """This machine's architecture token (its ``AUDIT_ARCH_*`` value)."""
    ffi, lib = _library()
    return int(lib.seccomp_arch_native())


def name(nr: int, arch: int = _ARCH_NATIVE) -> str:
    """The name of system call ``nr`` of architecture ``arch`` (an ``AUDIT_ARCH_*`` value, as
    the kernel reports it; 0: this machine's), ``syscall_N`` when libseccomp does not know it."""
    ffi, lib = _library()
    raw = lib.seccomp_syscall_resolve_num_arch(arch, nr)
    if raw == ffi.NULL:
        return f"syscall_{nr}"
    try:
        return ffi.string(raw).decode()
    finally:
        lib.free(raw)


class Filter:
    """A seccomp filter under construction: calls not matched by a rule get ``default``;
    calls of another architecture (32-bit calls on a 64-bit machine) get ``bad_arch``.

    ``keep_speculation``: do not let loading the filter turn on the kernel's speculative
    store bypass mitigation, which older kernels apply to every filtered process and which slows
    number crunching down; it protects a process's memory from its own code, and a lab's
    process holds nothing the lab cannot read anyway."""

    def __init__(self, default: int, *, bad_arch: int | None = None, keep_speculation: bool = False) -> None:
        self.ffi, self.lib = _library()
        self.ctx = self.lib.seccomp_init(default)
        if self.ctx == self.ffi.NULL:
            raise SeccompError(0, "seccomp_init failed")
        self._set(_ATTR_ACT_BADARCH, default if bad_arch is None else bad_arch)
        self._set(_ATTR_CTL_NNP, 1)  # set no_new_privs on load (unprivileged filters need it)
        self._set(_ATTR_CTL_TSYNC, 1)  # every thread of the process, not only the caller
        if keep_speculation:
            self.lib.seccomp_attr_set(self.ctx, _ATTR_CTL_SSB, 1)  # libseccomp < 2.5 lacks it: fine

    def _set(self, attr: int, value: int) -> None:
        rc = self.lib.seccomp_attr_set(self.ctx, attr, value)
        if rc < 0:
            raise SeccompError(-rc, f"seccomp_attr_set({attr}): {os.strerror(-rc)}")

    def add(self, action: int, syscall: str, *conditions: Cond) -> bool:
        """Give ``syscall`` (by name) ``action`` when every condition holds; a call this
        architecture does not have is skipped (returns False)."""
        nr = number(syscall)
        if nr < 0:
            return False
        conds = self.ffi.new("struct scmp_arg_cmp[]", max(1, len(conditions)))
        for i, c in enumerate(conditions):
            conds[i].arg, conds[i].op, conds[i].datum_a, conds[i].datum_b = c.arg, c.op, c.a, c.b
        rc = self.lib.seccomp_rule_add_array(self.ctx, action, nr, len(conditions), conds)
        if rc < 0:
            raise SeccompError(-rc, f"seccomp rule for {syscall}: {os.strerror(-rc)}")
        return True

    def load(self) -> None:
        """Apply the filter to this process, for good (it is inherited by any child)."""
        rc = self.lib.seccomp_load(self.ctx)
        if rc < 0:
            raise SeccompError(-rc, f"seccomp_load: {os.strerror(-rc)}")

    def release(self) -> None:
        """Free the filter's memory (a loaded filter stays loaded)."""
        if self.ctx != self.ffi.NULL:
            self.lib.seccomp_release(self.ctx)
            self.ctx = self.ffi.NULL

    def __enter__(self) -> Filter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()
