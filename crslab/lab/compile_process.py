"""One run of a compiler on a lab file, contained: whatever the file makes the compiler do (include
``/dev/urandom``, a huge ``.fill``, a preprocessor loop), it stops at limits and leaves nothing
behind.

- its own process group, killed whole when it is done or out of time (so no ``cc1`` or ``as``
  outlives ``crslab grade``);
- limits on its address space, CPU time and the size of any file it writes (the image included);
- stdin closed; what it prints kept up to :data:`MESSAGES_CAP` bytes;
- and, when given, the compile sandbox's Landlock ruleset (:mod:`crslab.sandbox.compile_sandbox`),
  applied just before ``exec``.

>>> r = run_compile(["sh", "-c", "echo to-stderr >&2; exit 3"], env={"PATH": os.environ["PATH"]})
>>> r.returncode, r.stderr, r.timed_out
(3, 'to-stderr\\n', False)
"""

from __future__ import annotations

import os
import resource
import signal
import subprocess
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

COMPILE_TIMEOUT_S = 60.0
"""Wall-clock time one compiler run may take."""
COMPILE_CPU_S = 60
"""CPU time one compiler process may use."""
COMPILE_MEMORY_BYTES = 4 * 1024 ** 3
"""Address space one compiler process may map (clang and cc1 need a few hundred MB)."""
FILE_SIZE_BYTES = 64 * 1024 * 1024
"""The largest file a compiler process may write (objects, temporaries; the image is checked
against its own, smaller cap after the build)."""
MESSAGES_CAP = 1024 * 1024
"""What is kept of the compiler's messages."""


@dataclass(frozen=True)
class CompileRun:
    """How a compiler run ended: its exit status (negative: the signal that ended it), its messages
    (stderr, then stdout), and whether it was stopped at the time limit."""

    returncode: int
    stderr: str
    timed_out: bool


def _limits(memory_bytes: int, cpu_s: int, file_bytes: int,
            then: Callable[[], None] | None) -> Callable[[], None]:
    def apply() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (memory_bytes, memory_bytes))
        resource.setrlimit(resource.RLIMIT_CPU, (cpu_s, cpu_s + 1))
        resource.setrlimit(resource.RLIMIT_FSIZE, (file_bytes, file_bytes))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if then is not None:
            then()
    return apply


def _kill_group(pgid: int) -> None:
    try:
        os.killpg(pgid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def run_compile(argv: Sequence[str], *, env: Mapping[str, str], preexec: Callable[[], None] | None = None,
                timeout_s: float = COMPILE_TIMEOUT_S, memory_bytes: int = COMPILE_MEMORY_BYTES,
                cpu_s: int = COMPILE_CPU_S, file_bytes: int = FILE_SIZE_BYTES,
                pass_fds: Sequence[int] = ()) -> CompileRun:
    """Run ``argv`` contained (see the module); raises ``OSError`` when it cannot be started."""
    proc = subprocess.Popen(list(argv), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env=dict(env), start_new_session=True, pass_fds=tuple(pass_fds),
                            preexec_fn=_limits(memory_bytes, cpu_s, file_bytes, preexec))
    timed_out = False
    try:
        out, err = proc.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        timed_out = True
        _kill_group(proc.pid)
        out, err = proc.communicate()
    finally:
        _kill_group(proc.pid)  # anything it started that is still running
    text = (err + b"\n" + out if out.strip() else err)[:MESSAGES_CAP]
    return CompileRun(proc.returncode, text.decode("utf-8", "replace"), timed_out)
