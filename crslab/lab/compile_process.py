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
from pathlib import Path

from crslab.sandbox.compile_sandbox import CompilerSandbox, forbidden_read

IMAGE_CAP_BYTES = 8 * 1024 * 1024
"""The largest firmware image (wasm module or shared object) a build may produce."""
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
                pass_fds: Sequence[int] = (), cwd: Path | None = None) -> CompileRun:
    """Run ``argv`` contained (see the module), in folder ``cwd`` (None: this process's); raises
    ``OSError`` when it cannot be started."""
    proc = subprocess.Popen(list(argv), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=dict(env), start_new_session=True, cwd=cwd,
                            pass_fds=tuple(pass_fds),
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


class LabBuildError(Exception):
    """The lab could not be built; ``diagnostics`` holds the compiler's own messages."""

    def __init__(self, message: str, diagnostics: str = "") -> None:
        super().__init__(message)
        self.diagnostics = diagnostics


class LabForbidden(LabBuildError):
    """The sandboxed compiler was refused a file the lab names (an ``#include`` of a path
    outside the lab's folder, a symbolic link out of it, an ``.incbin``): ``path`` is that file."""

    def __init__(self, message: str, diagnostics: str, path: str) -> None:
        super().__init__(message, diagnostics)
        self.path = path


def run_compiler(argv: list[str], what: str, sandbox: CompilerSandbox | None = None, *,
                 env: dict[str, str] | None = None, cwd: Path | None = None) -> str:
    """Run the compiler ``argv`` contained (inside ``sandbox`` when given; in folder ``cwd``, None:
    this process's); returns its messages; a failure is a LabBuildError (a LabForbidden when the
    sandbox refused a file)."""
    rules, preexec, pass_fds = None, None, ()
    environment = dict(env if env is not None else os.environ)
    if sandbox is not None:
        try:
            rules = sandbox.ruleset()
        except OSError as exc:  # Landlock missing: the caller should not have asked for the sandbox
            raise LabBuildError(f"the compile sandbox cannot be set up ({exc}); --no-sandbox compiles "
                                "without it") from None
        preexec, pass_fds = sandbox.preexec(rules.fd), (rules.fd,)
        for key in ("TMPDIR", "TMP", "TEMP"):
            environment[key] = str(sandbox.write)
    try:
        r = run_compile(argv, env=environment, preexec=preexec, pass_fds=pass_fds, cwd=cwd)
    except OSError as exc:
        raise LabBuildError(f"{Path(argv[0]).name} cannot be run ({exc.strerror})") from None
    finally:
        if rules is not None:
            rules.close()
    if r.timed_out:
        raise CompilerStopped(f"{what} does not compile: the compiler took longer than "
                              f"{COMPILE_TIMEOUT_S:.0f} s and was stopped", r.stderr)
    if r.returncode != 0:
        refused = forbidden_read(r.stderr) if sandbox is not None else None
        if refused:
            shown = f"{refused} (a symbolic link to {os.path.realpath(refused)})" \
                if os.path.islink(refused) else refused
            raise LabForbidden(f"{what} was stopped by the sandbox: it tried to read {shown} while "
                               "compiling (a lab may read only its own folder, crslab's headers and the "
                               "compiler's files)", r.stderr, refused)
        if r.returncode < 0:
            raise CompilerStopped(f"{what} does not compile: the compiler was stopped "
                                  f"({signal.Signals(-r.returncode).name}) at one of its limits: "
                                  f"{LIMITS_TEXT}", r.stderr)
        raise LabBuildError(f"{what} does not compile", r.stderr)
    return r.stderr


LIMITS_TEXT = (f"{COMPILE_CPU_S} s of CPU, {COMPILE_MEMORY_BYTES // 2**30} GB of memory, files of "
               f"{FILE_SIZE_BYTES // 2**20} MB")
"""What a compiler run may use, said when it is stopped."""


class CompilerStopped(LabBuildError):
    """The compiler was stopped at one of its limits (the lab made it run away)."""


def check_image(image: Path, what: str) -> None:
    """Refuse (and delete) a built image larger than :data:`IMAGE_CAP_BYTES`."""
    size = image.stat().st_size
    if size > IMAGE_CAP_BYTES:
        image.unlink()
        raise LabBuildError(f"{what} does not compile: its image is {size / 2**20:.0f} MB, more than the "
                            f"{IMAGE_CAP_BYTES // 2**20} MB crslab builds (the F28335 has 512 KB of flash)")
