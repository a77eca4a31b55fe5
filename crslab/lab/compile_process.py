"""The one way a compiler meets a submission: every compilation of a lab's text (the WebAssembly
build, the native build, the C28x check) goes through :class:`PrivateBuild` and :func:`run_compile`
(:func:`start_compile`), and nothing else in crslab starts a compiler on it
(tests/test_hostile_compile.py). Whatever the file makes the compiler do (include ``/dev/urandom``
or a neighbour's file, a huge ``.fill``, a preprocessor loop), it stops at limits, sees nothing but
its own folder and leaves nothing behind:

- a private copy: the compiler reads a copy of the lab's folder's allowed files
  (:func:`allowed_files`: regular files, a symbolic link only to one inside the folder, within
  sizes), never the folder itself, so a class folder, a FIFO, a link out of the folder are not
  there;
- the overlay and the sandbox (:mod:`crslab.sandbox.compile_sandbox`): everything else does not
  exist (clang's ``-ivfsoverlay``) and cannot be read (Landlock); "not there" and "not allowed"
  get one answer (:func:`same_answer`), so no message tells whether a file outside exists;
- its own process group, killed whole when it is done, out of time or interrupted (Ctrl-C,
  SIGTERM), and when crslab itself dies: the compiler gets SIGKILL when its parent dies
  (``PR_SET_PDEATHSIG``, set before ``exec``) and a reaper (:class:`Reaper`, a shell holding a pipe
  from crslab) kills its group and removes the build's folder when that pipe closes without a
  word, so neither a ``cc1`` nor the submission's text outlives a job killed on its time;
- limits on its address space, CPU time and the size of any file it writes (the image included);
- stdin closed; what it prints kept up to :data:`MESSAGES_CAP` bytes.

>>> r = run_compile(["sh", "-c", "echo to-stderr >&2; exit 3"], env={"PATH": os.environ["PATH"]})
>>> r.returncode, r.stderr, r.timed_out
(3, 'to-stderr\\n', False)
"""

from __future__ import annotations

import ctypes
import json
import os
import re
import resource
import shutil
import signal
import subprocess
import tempfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from crslab.sandbox.compile_sandbox import CompilerSandbox

IMAGE_CAP_BYTES = 8 * 1024 * 1024
"""The largest firmware image (wasm module or shared object) a build may produce."""
COMPILE_TIMEOUT_S = 60.0
"""Wall-clock time one compiler run may take."""
COMPILE_CPU_S = 60
"""CPU time one compiler process may use."""
COMPILE_MEMORY_BYTES = 2 * 1024 ** 3
"""Address space one compiler process may map (zig's clang needs under 1 GB for a lab; so
``--max-sessions`` builds at once take at most 2 GB each)."""
FILE_SIZE_BYTES = 64 * 1024 * 1024
"""The largest file a compiler process may write (objects, temporaries; the image is checked
against its own, smaller cap after the build)."""
MESSAGES_CAP = 1024 * 1024
"""What is kept of the compiler's messages."""
COPY_MAX_FILES = 200
"""How many files of a lab's folder its private copy holds at most (a lab has a few headers)."""
COPY_MAX_FILE_BYTES = 4 * 1024 * 1024
"""A larger file of the lab's folder is not in the copy (it is not there, for the compiler)."""
COPY_MAX_BYTES = 32 * 1024 * 1024
"""The copy's size in all."""
COPY_MAX_DEPTH = 3
"""How deep into the lab's folder's subfolders the copy goes."""
COPY_MAX_ENTRIES = 2000
"""How many entries of the lab's folder and its subfolders are looked at in all (a lab in a home
folder must not make every build walk it)."""
SOURCE_FOLDER = "submission"
"""The folder of a private build holding the copy."""


@dataclass(frozen=True)
class CompileRun:
    """How a compiler run ended: its exit status (negative: the signal that ended it), its messages
    (stderr, then stdout), and whether it was stopped at the time limit."""

    returncode: int
    stderr: str
    timed_out: bool


def allowed_files(folder: Path, leave_out: Sequence[Path] = ()) -> list[tuple[str, Path, int]]:
    """The files of ``folder`` a compiler may see, as (name from the folder, path, size in bytes),
    in a stable order: regular files (a symbolic link only when it leads to a regular file inside
    the folder), :data:`COPY_MAX_DEPTH` folders deep (hidden folders and the folders ``leave_out``
    left out: crslab's build cache, when it lies in the lab's folder, is no part of the lab and
    changes with every build), each at most
    :data:`COPY_MAX_FILE_BYTES`, at most :data:`COPY_MAX_FILES` of them and :data:`COPY_MAX_BYTES`
    in all. A FIFO, a socket, a device, a link out of the folder are not among them.

    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp()); _ = (d / "lab.c").write_text("int x;"); os.mkfifo(d / "f.h")
    >>> (d / "out.h").symlink_to("/etc/hostname"); (d / "in.h").symlink_to(d / "lab.c")
    >>> [(name, size) for name, _, size in allowed_files(d)]
    [('in.h', 6), ('lab.c', 6)]
    """
    root = os.path.realpath(folder)
    left_out = {os.path.realpath(f) for f in leave_out}
    out: list[tuple[str, Path, int]] = []
    total = 0
    level = [("", Path(folder))]
    seen = 0
    for depth in range(COPY_MAX_DEPTH + 1):
        below: list[tuple[str, Path]] = []
        for prefix, here in level:
            try:
                entries = sorted(os.scandir(here), key=lambda e: e.name)
            except OSError:
                continue
            for entry in entries:
                seen += 1
                if seen > COPY_MAX_ENTRIES:
                    return out
                name = prefix + entry.name
                try:
                    if entry.is_dir(follow_symlinks=False):
                        if (depth < COPY_MAX_DEPTH and not entry.name.startswith(".")
                                and os.path.realpath(entry.path) not in left_out):
                            below.append((name + "/", Path(entry.path)))
                        continue
                    real = os.path.realpath(entry.path)
                    if not real.startswith(root + os.sep):
                        continue
                    st = os.stat(real)
                except OSError:
                    continue
                if not stat_is_regular(st.st_mode) or st.st_size > COPY_MAX_FILE_BYTES:
                    continue
                if total + st.st_size > COPY_MAX_BYTES or len(out) >= COPY_MAX_FILES:
                    return out
                total += st.st_size
                out.append((name, Path(real), st.st_size))
        level = below
    return out


def stat_is_regular(mode: int) -> bool:
    """Whether ``mode`` is a regular file's."""
    import stat

    return stat.S_ISREG(mode)


def folder_listing(files: list[tuple[str, Path, int]]) -> list[str]:
    """What the names of the allowed files tell a compiler without reading them (``__has_include``,
    ``__has_embed``: whether a file is there, and whether it is empty): part of a build's name.

    >>> folder_listing([("gains.h", Path("/x/gains.h"), 12), ("empty.bin", Path("/x/empty.bin"), 0)])
    ['gains.h', 'empty.bin (empty)']
    """
    return [name + (" (empty)" if size == 0 else "") for name, _, size in files]


def copy_name(name: str) -> str:
    """The name of the build's copy of a lab named ``name``: the same, unless an ``#include`` cannot
    spell it (a quote or a line break), so messages and backtraces name the lab as the user does.

    >>> copy_name("my lab.c"), copy_name('=F("x").c')
    ('my lab.c', '_F__x__.c')
    """
    return re.sub(r"[^\w.+-]", "_", name) if any(ch in name for ch in '"\n\r') else name


_REAPER = r"""
g=
while IFS= read -r l; do
  case "$l" in
    +*) g="${l#+}" ;;
    -) g= ;;
    done) exit 0 ;;
  esac
done
[ -n "$g" ] && kill -s KILL -- "-$g" 2>/dev/null
[ -n "$1" ] && rm -rf -- "$1"
exit 0
"""


class Reaper:
    """A shell that outlives crslab to clean after it: told the process group of the compiler
    running now, it kills that group and removes ``folder`` when its pipe from crslab closes without
    ``done`` (crslab was killed: grade's ``--timeout``, SIGKILL, a crash)."""

    def __init__(self, folder: Path | None = None) -> None:
        self._proc = subprocess.Popen(["/bin/sh", "-c", _REAPER, "crslab-reaper", str(folder or "")],
                                      stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL, start_new_session=True)

    def _say(self, line: str) -> None:
        stdin = self._proc.stdin
        if stdin is not None and not stdin.closed:
            try:
                stdin.write(line.encode() + b"\n")
                stdin.flush()
            except (BrokenPipeError, ValueError):
                pass

    def watch(self, pgid: int) -> None:
        """The compiler's group that runs now."""
        self._say(f"+{pgid}")

    def unwatch(self) -> None:
        """That group is gone (crslab killed and reaped it)."""
        self._say("-")

    def done(self) -> None:
        """crslab cleans up itself: the reaper ends without touching anything."""
        self._say("done")
        if self._proc.stdin is not None:
            try:
                self._proc.stdin.close()
            except BrokenPipeError:
                pass
        try:
            self._proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self._proc.kill()
            self._proc.wait()


_libc = ctypes.CDLL(None, use_errno=True)
PR_SET_PDEATHSIG = 1


ENDING_SIGNALS = {signal.SIGINT, signal.SIGTERM, signal.SIGHUP}
"""Held back while a compiler is started and recorded, so that no Ctrl-C or SIGTERM can leave one
started that nobody kills."""


def _limits(memory_bytes: int, cpu_s: int, file_bytes: int, parent: int, mask: set[signal.Signals],
            then: Callable[[], None] | None) -> Callable[[], None]:
    prctl = _libc.prctl

    def apply() -> None:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        if os.getppid() != parent:  # crslab died before the line above: end now
            os._exit(1)
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


class CompileProcess:
    """A compiler started by :func:`start_compile`; :meth:`wait` for it (or :meth:`kill` it)."""

    def __init__(self, argv: Sequence[str], *, env: Mapping[str, str], preexec: Callable[[], None] | None,
                 memory_bytes: int, cpu_s: int, file_bytes: int, pass_fds: Sequence[int],
                 cwd: Path | None, reaper: Reaper | None) -> None:
        self._own_reaper = reaper is None
        self._ended = False
        mask = signal.pthread_sigmask(signal.SIG_BLOCK, ENDING_SIGNALS)
        try:
            self.reaper = reaper if reaper is not None else Reaper()
            try:
                self.proc = subprocess.Popen(list(argv), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                             stderr=subprocess.PIPE, env=dict(env), start_new_session=True,
                                             cwd=cwd, pass_fds=tuple(pass_fds),
                                             preexec_fn=_limits(memory_bytes, cpu_s, file_bytes, os.getpid(),
                                                                mask, preexec))
            except BaseException:
                if self._own_reaper:
                    self.reaper.done()
                raise
            self.reaper.watch(self.proc.pid)
        finally:
            try:
                signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a signal held back acts here
            except BaseException:
                if hasattr(self, "proc"):
                    self.kill()
                raise

    def wait(self, timeout_s: float = COMPILE_TIMEOUT_S) -> CompileRun:
        """Wait for it, at most ``timeout_s`` (then it is killed); whatever ends the wait (a
        KeyboardInterrupt: Ctrl-C, SIGTERM), its whole group is killed."""
        timed_out = False
        try:
            out, err = self.proc.communicate(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            timed_out = True
            _kill_group(self.proc.pid)
            out, err = self.proc.communicate()
        finally:
            self.kill()
        text = (err + b"\n" + out if out.strip() else err)[:MESSAGES_CAP]
        return CompileRun(self.proc.returncode, text.decode("utf-8", "replace"), timed_out)

    def kill(self) -> None:
        """Kill its whole group (the compiler's children too) and reap it."""
        if self._ended:
            return
        self._ended = True
        _kill_group(self.proc.pid)  # the group lives while one of it does: the id is still its
        self.proc.kill()
        self.proc.wait()
        for stream in (self.proc.stdout, self.proc.stderr):
            if stream is not None:
                stream.close()
        self.reaper.unwatch()
        if self._own_reaper:
            self.reaper.done()


def start_compile(argv: Sequence[str], *, env: Mapping[str, str], preexec: Callable[[], None] | None = None,
                  memory_bytes: int = COMPILE_MEMORY_BYTES, cpu_s: int = COMPILE_CPU_S,
                  file_bytes: int = FILE_SIZE_BYTES, pass_fds: Sequence[int] = (), cwd: Path | None = None,
                  reaper: Reaper | None = None) -> CompileProcess:
    """Start ``argv`` contained (see the module), in folder ``cwd`` (None: this process's), watched
    by ``reaper`` (None: one of its own); raises ``OSError`` when it cannot be started. The only
    place crslab starts a compiler."""
    return CompileProcess(argv, env=env, preexec=preexec, memory_bytes=memory_bytes, cpu_s=cpu_s,
                          file_bytes=file_bytes, pass_fds=pass_fds, cwd=cwd, reaper=reaper)


def run_compile(argv: Sequence[str], *, env: Mapping[str, str], preexec: Callable[[], None] | None = None,
                timeout_s: float = COMPILE_TIMEOUT_S, memory_bytes: int = COMPILE_MEMORY_BYTES,
                cpu_s: int = COMPILE_CPU_S, file_bytes: int = FILE_SIZE_BYTES,
                pass_fds: Sequence[int] = (), cwd: Path | None = None,
                reaper: Reaper | None = None) -> CompileRun:
    """:func:`start_compile`, then wait for it (at most ``timeout_s``)."""
    return start_compile(argv, env=env, preexec=preexec, memory_bytes=memory_bytes, cpu_s=cpu_s,
                         file_bytes=file_bytes, pass_fds=pass_fds, cwd=cwd, reaper=reaper).wait(timeout_s)


class PrivateBuild:
    """A build's private folder (in ``parent``, else the system's temporary folder): ``source`` holds
    a copy of the lab's folder's allowed files (:func:`allowed_files`; none when ``alone``: a
    class's submission, whose folder holds the others), the lab itself as ``copy`` (its ``text``,
    read once); a :class:`Reaper` removes the folder if crslab dies before :meth:`close` does. The
    folders ``leave_out`` (the build cache) are not copied. Use it as a context manager."""

    def __init__(self, lab: Path, text: bytes, parent: Path | None = None, *, alone: bool = False,
                 leave_out: Sequence[Path] = ()) -> None:
        self.lab = Path(lab)
        self.folder = Path(tempfile.mkdtemp(prefix="crslab-build-", dir=parent))
        self.reaper = Reaper(self.folder)
        self.source = self.folder / SOURCE_FOLDER
        self.source.mkdir()
        self.files = [] if alone else allowed_files(self.lab.absolute().parent, leave_out)
        for name, path, _ in self.files:
            target = self.source / name
            target.parent.mkdir(parents=True, exist_ok=True)
            try:
                shutil.copyfile(path, target)
            except OSError:
                continue
        self.copy = self.source / copy_name(self.lab.name)
        self.copy.write_bytes(text)

    def read_from_folder(self, paths: Sequence[str]) -> list[str]:
        """Of the files a compiler said it read (``paths``, absolute or from the build's folder),
        the names (from the lab's folder) of those in the copy, the lab itself left out."""
        names = []
        for p in paths:
            full = Path(os.path.normpath(self.folder / p))
            if self.source in full.parents and full != self.copy:
                names.append(full.relative_to(self.source).as_posix())
        return sorted(set(names))

    def close(self) -> None:
        self.reaper.done()
        shutil.rmtree(self.folder, ignore_errors=True)

    def __enter__(self) -> PrivateBuild:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def visible_files(build_dir: Path, folders: list[Path]) -> Path:
    """A file-system overlay for clang (``-ivfsoverlay``) in which only ``folders`` exist: the lab's
    build's folder (holding its private copy), crslab's headers, zig's C library. Everything else
    is not found, as if it were not there, so ``#include`` and ``__has_include`` of a path outside
    cannot even tell whether a file exists (the compile sandbox, which refuses to read it, would).
    Returns its path.

    >>> import tempfile
    >>> path = visible_files(Path(tempfile.mkdtemp()), [Path("/labs/me")])
    >>> json.loads(path.read_text())["roots"][0]["name"]
    '/labs/me'
    """
    roots = [{"name": str(f), "type": "directory-remap", "external-contents": str(f)}
             for f in dict.fromkeys(folders)]
    path = build_dir / "visible-files.json"
    path.write_text(json.dumps({"version": 0, "fallthrough": False, "roots": roots}))
    return path


def dependencies(make_rule: str) -> list[str]:
    """The files a compiler's ``-MD -MF`` output says it read (its prerequisites).

    >>> splice, newline = chr(92) + chr(10), chr(10)  # a backslash ending a line; a line's end
    >>> dependencies("/tmp/x/lab.o: lab.c signs.h " + splice + "  /b/my" + chr(92) + " data.bin" + newline)
    ['lab.c', 'signs.h', '/b/my data.bin']
    """
    _, _, rest = make_rule.partition(": ")
    rest = rest.replace("\\\n", " ")
    words = re.findall(r"(?:\\.|[^\s\\])+", rest)
    return [re.sub(r"\\(.)", r"\1", w) for w in words]


class LabBuildError(Exception):
    """The lab could not be built; ``diagnostics`` holds the compiler's own messages."""

    def __init__(self, message: str, diagnostics: str = "") -> None:
        super().__init__(message)
        self.diagnostics = diagnostics


class LabForbidden(LabBuildError):
    """The sandbox refused the lab a file (a submission that is a symbolic link out of the class
    folder): ``path`` is that file."""

    def __init__(self, message: str, diagnostics: str, path: str) -> None:
        super().__init__(message, diagnostics)
        self.path = path


_DENIED = (
    (re.compile(r"cannot open file '(.+?)': Permission denied"), r"'\1' file not found"),      # clang
    (re.compile(r"error: (.+?): Permission denied"), r"error: \1: No such file or directory"),  # gcc
    (re.compile(r"can't open (.+?) for reading: Permission denied"),
     r"can't open \1 for reading: No such file or directory"),                                  # as
    (re.compile(r"cannot open (.+?): Permission denied"), r"cannot open \1: No such file or directory"),
)


def same_answer(diagnostics: str) -> str:
    """The compiler's messages with "not allowed" said as "not there": a file the sandbox refused
    and a file that does not exist read alike, so no message tells whether a file outside the lab's
    folder exists.

    >>> same_answer("lab.c:3:10: fatal error: /home/ta/key.h: Permission denied")
    'lab.c:3:10: fatal error: /home/ta/key.h: No such file or directory'
    >>> same_answer("lab.c:3:10: fatal error: cannot open file '/home/ta/key.h': Permission denied")
    "lab.c:3:10: fatal error: '/home/ta/key.h' file not found"
    """
    for pattern, said in _DENIED:
        diagnostics = pattern.sub(said, diagnostics)
    return diagnostics


def run_compiler(argv: list[str], what: str, sandbox: CompilerSandbox | None = None, *,
                 env: dict[str, str] | None = None, cwd: Path | None = None,
                 reaper: Reaper | None = None) -> str:
    """Run the compiler ``argv`` contained (inside ``sandbox`` when given; in folder ``cwd``, None:
    this process's; watched by ``reaper``); returns its messages; a failure is a LabBuildError
    whose messages never tell a refused file from a missing one (:func:`same_answer`)."""
    running = start_sandboxed(argv, sandbox, env=env, cwd=cwd, reaper=reaper)
    r = running.wait()
    text = same_answer(r.stderr) if sandbox is not None else r.stderr
    if r.timed_out:
        raise CompilerStopped(f"{what} does not compile: the compiler took longer than "
                              f"{COMPILE_TIMEOUT_S:.0f} s and was stopped", text)
    if r.returncode != 0:
        if r.returncode < 0:
            raise CompilerStopped(f"{what} does not compile: the compiler was stopped "
                                  f"({signal.Signals(-r.returncode).name}) at one of its limits: "
                                  f"{LIMITS_TEXT}", text)
        raise LabBuildError(f"{what} does not compile", text)
    return text


class _Sandboxed:
    """A compiler started in a sandbox: its ruleset's descriptor is closed when it is waited for."""

    def __init__(self, running: CompileProcess, rules: object | None) -> None:
        self.running, self._rules = running, rules

    def wait(self, timeout_s: float = COMPILE_TIMEOUT_S) -> CompileRun:
        try:
            return self.running.wait(timeout_s)
        finally:
            self.close()

    def kill(self) -> None:
        self.running.kill()
        self.close()

    def close(self) -> None:
        if self._rules is not None:
            self._rules.close()  # type: ignore[attr-defined]
            self._rules = None


def start_sandboxed(argv: Sequence[str], sandbox: CompilerSandbox | None, *,
                    env: Mapping[str, str] | None = None, cwd: Path | None = None,
                    reaper: Reaper | None = None) -> _Sandboxed:
    """:func:`start_compile` inside ``sandbox`` (None: without), its temporary files in the
    sandbox's writable folder; raises LabBuildError when it cannot be started."""
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
        running = start_compile(argv, env=environment, preexec=preexec, pass_fds=pass_fds, cwd=cwd,
                                reaper=reaper)
    except OSError as exc:
        if rules is not None:
            rules.close()
        raise LabBuildError(f"{Path(argv[0]).name} cannot be run ({exc.strerror})") from None
    return _Sandboxed(running, rules)


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
