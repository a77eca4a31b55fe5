"""The sandbox every lab is compiled and run in: a student's file may compute and print, and
nothing else (no files, no programs, no processes, no network, no signals to others, no ptrace).

Made of what the kernel and well-kept tools give, all unprivileged:

- compiling (:mod:`~crslab.sandbox.compile_sandbox`): Landlock lets the compiler read the lab's
  folder, crslab's headers and the system's compiler, and write only the build folder;
- running (:mod:`~crslab.sandbox.run_sandbox`): the worker process, once MuJoCo is loaded and
  before the lab's shared object is, closes itself with Landlock (no file, no TCP, no signal
  out) and a seccomp allow-list built with libseccomp (:mod:`~crslab.sandbox.syscalls`); a
  refused call traps into a small C handler (:mod:`~crslab.sandbox.trap`) that records it for
  the one-line diagnosis (:mod:`~crslab.sandbox.refusal`).

:func:`resolve` turns a command's wish into a decision; docs/architecture.md says why these
mechanisms and not others.
"""

from __future__ import annotations

import warnings

from crslab.sandbox.support import missing, support


class SandboxUnavailable(RuntimeError):
    """The sandbox was required and this machine lacks a protection it needs."""


def resolve(requested: bool | None) -> bool:
    """Whether to sandbox: ``True`` requires it (raises :class:`SandboxUnavailable` naming what
    is missing), ``False`` turns it off, ``None`` uses it when this machine has it (with a
    warning when it does not).

    >>> resolve(False)
    False
    """
    if requested is False:
        return False
    lacking = missing()
    if not lacking:
        return True
    text = "; ".join(lacking)
    if requested:
        raise SandboxUnavailable(f"the sandbox needs {text}")
    warnings.warn(f"running without the sandbox: this machine lacks {text}", stacklevel=2)
    return False


__all__ = ["SandboxUnavailable", "missing", "resolve", "support"]
