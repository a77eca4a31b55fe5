"""The debuggers ``crslab debug`` runs: gdb for the terminal, gdbserver for an IDE. A missing
one is a :class:`DebuggerMissing` whose message is one line saying how to install it.

>>> try:
...     find_debugger("gdb", search_path="/nonexistent")
... except DebuggerMissing as exc:
...     print(exc)
gdb is not installed: 'sudo apt install gdb' (Debian, Ubuntu, WSL) or 'sudo dnf install gdb' (Fedora)
"""

from __future__ import annotations

import os
import shutil
import subprocess

INSTALL = {
    "gdb": "'sudo apt install gdb' (Debian, Ubuntu, WSL) or 'sudo dnf install gdb' (Fedora)",
    "gdbserver": "'sudo apt install gdbserver' (Debian, Ubuntu, WSL) or 'sudo dnf install gdb-gdbserver' "
                 "(Fedora)",
}


class DebuggerMissing(FileNotFoundError):
    """The debugger is not on PATH (or cannot serve crslab): ``what`` is wrong, ``fix`` says how to
    install it; the message is both, in one line."""

    def __init__(self, what: str, fix: str) -> None:
        super().__init__(f"{what}: {fix}")
        self.what = what
        self.fix = fix


def find_debugger(name: str, search_path: str | None = None) -> str:
    """The path of ``gdb`` or ``gdbserver`` on PATH."""
    found = shutil.which(name, path=search_path if search_path is not None else os.environ.get("PATH"))
    if found is None:
        raise DebuggerMissing(f"{name} is not installed", INSTALL[name])
    return found


PYTHON_PROBE = "python print('crslab-python-ok')"
PROBE_TIMEOUT_S = 30.0


def check_gdb_python(gdb: str) -> None:
    """crslab's gdb setup is Python run inside gdb (:mod:`crslab.debug.in_gdb`): a gdb built
    without Python (Debian's ``gdb-minimal``) is a :class:`DebuggerMissing` saying so."""
    try:
        r = subprocess.run([gdb, "-nx", "-batch", "-ex", PYTHON_PROBE], capture_output=True, text=True,
                           timeout=PROBE_TIMEOUT_S)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise DebuggerMissing(f"{gdb} does not run ({exc})", f"install gdb: {INSTALL['gdb']}") from None
    if "crslab-python-ok" not in r.stdout:
        raise DebuggerMissing(f"{gdb} was built without Python, which crslab debug needs (a minimal gdb)",
                              f"install the full gdb: {INSTALL['gdb']}")


def debugger_for(console: bool) -> str:
    """The debugger a run needs, checked: gdb with Python for the terminal, else gdbserver."""
    if not console:
        return find_debugger("gdbserver")
    gdb = find_debugger("gdb")
    check_gdb_python(gdb)
    return gdb


def gdb_version(gdb: str) -> str:
    """The first line of ``gdb --version`` (e.g. ``GNU gdb (Debian 13.1-3) 13.1``)."""
    try:
        r = subprocess.run([gdb, "--version"], capture_output=True, text=True, timeout=PROBE_TIMEOUT_S)
    except (OSError, subprocess.TimeoutExpired):
        return "unknown version"
    return (r.stdout.splitlines() or ["unknown version"])[0]

