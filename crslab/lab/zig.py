"""zig, the C compiler crslab builds WebAssembly firmware with (``zig cc``: clang with a C library for
wasm32), from the ``ziglang`` package on PyPI, so no system compiler is needed.

zig's first link for a target builds that target's C library (1 to 2 minutes of CPU). crslab does
it once per installation (:func:`prepare`: ``make venv``, ``crslab doctor``, or else the first
build, with a note and a running clock on stderr, never silently) and keeps the result beside
crslab, keyed to zig's version and the link flags (:data:`LIBC_FOLDER`); a lab is then compiled
with ``-nostdlib`` and linked with the kept objects, so zig never builds it again, even in a fresh
cache. zig's own cache lives in crslab's (``<cache>/zig``), so clearing one clears both.

>>> zig_cc()[-1]
'cc'
>>> zig_cc()[0].endswith("zig")
True
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import os
import re
import shutil
import stat
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import TextIO

from crslab.cache import CacheError, cache_dir, read_own, subfolder, usable_problem
from crslab.sandbox.compile_sandbox import include_search_dirs

FIRST_USE_TIMEOUT_S = 1800.0
"""How long zig's build of a C library may take (40-150 s measured on 2 cores, 5 to over 10 minutes
while 8 other jobs share them)."""
PREPARE_MEMORY_BYTES = 8 * 1024 ** 3
"""The address space zig may map while it builds its C library (crslab's own sources, in threads)."""


class ZigMissing(FileNotFoundError):
    """The ``ziglang`` package is not installed (it comes with crslab)."""


def zig_dir() -> Path:
    """The folder of the ``ziglang`` package: the zig program, its C library's sources."""
    spec = importlib.util.find_spec("ziglang")
    if spec is None or not spec.submodule_search_locations:
        raise ZigMissing("zig is missing: reinstall crslab (it depends on the ziglang package)")
    return Path(next(iter(spec.submodule_search_locations)))


def zig_program() -> Path:
    """The zig program itself (run directly: no Python start-up per compile)."""
    exe = zig_dir() / ("zig.exe" if sys.platform == "win32" else "zig")
    if not exe.is_file():
        raise ZigMissing(f"zig is missing from {exe.parent}: reinstall the ziglang package")
    return exe


def zig_cc() -> list[str]:
    """The command that runs zig's C compiler (followed by clang's own arguments)."""
    return [str(zig_program()), "cc"]


@cache
def zig_version() -> str:
    """zig's version, as the ``ziglang`` package records it: the name of its one ``.dist-info``
    folder beside the package, else importlib.metadata's answer (a cached build's key needs the
    version at every command's start, and importing importlib.metadata costs it tens of ms).

    >>> from importlib.metadata import version
    >>> zig_version() == version("ziglang")
    True
    """
    infos = list(zig_dir().parent.glob("ziglang-*.dist-info"))
    if len(infos) == 1:
        return infos[0].name.removeprefix("ziglang-").removesuffix(".dist-info")
    from importlib.metadata import version

    return version("ziglang")


ZIG_CACHE_ENV = "ZIG_GLOBAL_CACHE_DIR"
"""zig's own setting for its global cache; crslab uses it when it is set."""


def zig_cache() -> Path:
    """zig's global cache (the C libraries it builds once per target): ``$ZIG_GLOBAL_CACHE_DIR``
    when set, else ``zig/`` in crslab's build cache; either checked as it is used (this user's, not
    written by others: :class:`crslab.cache.CacheError` says why not).

    >>> import os, tempfile
    >>> os.environ[ZIG_CACHE_ENV] = tempfile.mkdtemp()
    >>> zig_cache() == Path(os.environ.pop(ZIG_CACHE_ENV))
    True
    """
    own = os.environ.get(ZIG_CACHE_ENV)
    if not own:
        return subfolder(cache_dir(), "zig")
    why = usable_problem(Path(own))
    if why is not None:
        raise CacheError(f"{ZIG_CACHE_ENV}={own} cannot be used as zig's cache: {why}")
    return Path(own)


def zig_environment(local_cache: Path | None = None) -> dict[str, str]:
    """The environment zig runs in: its global cache in crslab's, and the build's own local cache."""
    env = dict(os.environ)
    env[ZIG_CACHE_ENV] = str(zig_cache())
    if local_cache is not None:
        env["ZIG_LOCAL_CACHE_DIR"] = str(local_cache)
    return env


LIBC_FOLDER = "zig-libc"
"""Where a prepared C library lives: in the environment crslab is installed in
(``<prefix>/share/crslab/zig-libc``, made at install: ``make venv``, ``crslab doctor``), else in
the per-user cache (``<cache>/zig-libc``) when the environment is read-only."""


@dataclass(frozen=True)
class LibC:
    """zig's C library for one target and set of link flags, built once and kept apart from zig's
    cache: a lab is then compiled without the C library (``-nostdlib``, so zig never builds one),
    with its headers (:attr:`includes`) and linked with its objects (:attr:`link`)."""

    folder: Path
    includes: tuple[Path, ...]
    link: tuple[Path, ...]

    def compile_flags(self) -> list[str]:
        """What a compile (and link) with this library adds to ``zig cc``'s command."""
        flags = ["-nostdlib"]
        for folder in self.includes:
            flags += ["-isystem", str(folder)]
        return flags


LIBC_ENV = "CRSLAB_ZIG_LIBC_DIR"
"""A folder to keep the prepared C library in instead (a read-only installation, a test)."""


def libc_homes() -> list[Path]:
    """Where a prepared C library is looked for, in order (see :data:`LIBC_FOLDER`; ``$CRSLAB_ZIG_LIBC_DIR``
    alone when it is set)."""
    if os.environ.get(LIBC_ENV):
        return [Path(os.environ[LIBC_ENV])]
    homes = [Path(sys.prefix) / "share" / "crslab" / LIBC_FOLDER]
    try:
        homes.append(subfolder(cache_dir(), LIBC_FOLDER))
    except OSError:  # no cache: the environment's alone
        pass
    return homes


class LibcRefused(RuntimeError):
    """A prepared C library that must not be linked into a lab; the message says whose or why."""


def trusted_owners() -> tuple[int, ...]:
    """Who may own a prepared C library crslab links into a lab: this user, root, and whoever owns
    zig itself (the installation: they could change the compiler as well)."""
    try:
        installer = zig_dir().stat().st_uid
    except (OSError, ZigMissing):
        installer = 0
    return tuple(dict.fromkeys((os.getuid(), 0, installer)))


def _folder_problem(folder: Path, owners: tuple[int, ...], *, follow: bool = False) -> str | None:
    """Why ``folder`` may not hold code crslab links (a link, not a folder, another owner, writable
    by its group or others), else None."""
    try:
        st = os.stat(folder) if follow else os.lstat(folder)
    except OSError as exc:
        return exc.strerror or str(exc)
    if stat.S_ISLNK(st.st_mode):
        return "it is a symbolic link"
    if not stat.S_ISDIR(st.st_mode):
        return "it is not a folder"
    if st.st_uid not in owners:
        return f"it belongs to another user (uid {st.st_uid})"
    if st.st_mode & 0o022:
        return "its group or others may write it"
    return None


_checked_libc: dict[tuple, bool] = {}
"""The libraries whose files' digests this process checked, by the files' identities."""


def _identity(path: Path) -> tuple[int, ...]:
    try:
        st = os.lstat(path)
    except OSError:
        return ()
    return (st.st_ino, st.st_dev, st.st_size, st.st_mtime_ns, st.st_ctime_ns, st.st_uid, st.st_mode)


def _file_digests(folder: Path, names: list[str], owners: tuple[int, ...]) -> dict[str, str] | str:
    """The sha256 of each file ``names`` of ``folder`` (read through one checked descriptor each:
    regular, not a link, of ``owners``, written by nobody else), or why one cannot be used."""
    digests = {}
    for name in names:
        data = read_own(folder / name, owners=owners)
        if data is None:
            return f"{name} is missing, a link, another user's or writable by others"
        digests[name] = hashlib.sha256(data).hexdigest()
    return digests


def _libc_at(folder: Path, home_named: bool) -> LibC | None:
    """The prepared C library in ``folder`` when it may be linked: the folder and every file of it
    owned by :func:`trusted_owners`, written by nobody else, not links, each file's sha256 the one
    its manifest recorded when it was built. None when there is none; :class:`LibcRefused` (one
    line) when there is one that may not be used in a folder the user named (``home_named``:
    ``$CRSLAB_ZIG_LIBC_DIR``), else None too (another home is tried, or it is built anew)."""
    owners = trusted_owners()

    def refused(why: str) -> None:
        if home_named:
            raise LibcRefused(f"{LIBC_ENV}: {folder} cannot be linked into a lab: {why}")

    if not os.path.lexists(folder):
        return None
    problem = _folder_problem(folder, owners)
    if problem is not None:
        return refused(problem)
    raw = read_own(folder / "manifest.json", owners=owners)
    try:
        manifest = json.loads(raw) if raw is not None else None
        names = [str(n) for n in manifest["link"]] if manifest else None
    except (ValueError, KeyError, TypeError):
        names = None
    if not manifest or not names or any("/" in n or n.startswith(".") for n in names):
        return refused("its manifest.json is missing, damaged, another user's or writable by others")
    stamp = (str(folder), *(_identity(folder / n) for n in ["manifest.json", *names]))
    if not _checked_libc.get(stamp):
        digests = _file_digests(folder, names, owners)
        if isinstance(digests, str):
            return refused(digests)
        recorded = manifest.get("sha256")
        if recorded is None:  # kept before digests were recorded: recorded now, when it is this user's
            _record_digests(folder, manifest, digests)
        elif recorded != digests:
            changed = sorted(n for n in names if recorded.get(n) != digests[n])
            return refused(f"{', '.join(changed)} changed since it was built")
        _checked_libc[stamp] = True
    lib = zig_dir() / "lib"
    return LibC(folder, tuple(lib / p for p in manifest["includes"]), tuple(folder / n for n in names))


def _record_digests(folder: Path, manifest: dict, digests: dict[str, str]) -> None:
    """Write ``digests`` into the manifest of a library kept without them (when this user may)."""
    if os.lstat(folder).st_uid != os.getuid():
        return
    try:
        part = folder / f".manifest.{os.getpid()}.part"
        part.write_text(json.dumps({**manifest, "sha256": digests}, indent=1))
        part.chmod(0o644)
        part.replace(folder / "manifest.json")
    except OSError:
        pass


def libc_name(target: str, flags: list[str]) -> str:
    """The folder name of a C library: the target, zig's version and the link flags.

    >>> libc_name("wasm32-wasi", ["-O2"]).startswith("wasm32-wasi-zig")
    True
    """
    digest = hashlib.sha256(" ".join(flags).encode()).hexdigest()[:12]
    return f"{target}-zig{zig_version()}-{digest}"


def prepared(target: str, flags: list[str]) -> LibC | None:
    """The C library for ``target`` and ``flags`` when it is already built (and may be linked: see
    :func:`_libc_at`), else None."""
    named = bool(os.environ.get(LIBC_ENV))
    for home in libc_homes():
        problem = _folder_problem(home, trusted_owners(), follow=True)
        if problem is not None:
            if named and os.path.exists(home):
                raise LibcRefused(f"{LIBC_ENV}={home} cannot hold the C library crslab links into a lab: "
                                  f"{problem}")
            continue
        libc = _libc_at(home / libc_name(target, flags), named)
        if libc is not None:
            return libc
    return None


def is_prepared(target: str, flags: list[str]) -> bool:
    """Whether zig's C library for ``target`` is already built (a compile then takes ~0.1 s)."""
    return prepared(target, flags) is not None


PROBE = ("#include <math.h>\n#include <stdio.h>\n#include <stdlib.h>\n"
         "int crs_probe(double x) { char b[32]; return snprintf(b, 32, \"%f\", sin(x)); }\n")


def link_inputs(verbose: str, cwd: Path) -> tuple[list[str], list[Path]]:
    """From ``zig cc -v``'s messages: the C library's include folders (those under zig's ``lib``, as
    paths inside it) and what the linker was given besides the program's own object: the start-up
    object and the libraries (absolute paths).

    >>> inc, link = link_inputs("#include <...> search starts here:\\n /z/lib/include\\n"
    ...                         " /z/lib/libc/include/x\\nEnd of search list.\\n"
    ...                         "wasm-ld -o p c/o/1/crt1-reactor.o l/o/2/probe.o "
    ...                         "c/o/3/libc.a", Path("/t"))
    >>> link
    [PosixPath('/t/c/o/1/crt1-reactor.o'), PosixPath('/t/c/o/3/libc.a')]
    """
    includes = include_search_dirs(verbose)
    link: list[Path] = []
    command = next((line for line in verbose.splitlines() if line.startswith("wasm-ld ")), "")
    for word in command.split():
        if (word.endswith(".a") or re.search(r"crt1[\w-]*\.o$", word)) and "probe" not in word:
            link.append(cwd / word)
    return includes, link


def prepare(target: str, flags: list[str], stream: TextIO | None = None) -> LibC:
    """zig's C library for ``target``, built once for link ``flags`` (a tiny program compiled and
    linked), saying so on ``stream`` (default stderr) with the seconds it has taken so far (a
    running clock on a terminal, a line every :data:`PROGRESS_EVERY_S` elsewhere), and kept (see
    :data:`LIBC_FOLDER`). Raises ``RuntimeError`` with zig's message when zig cannot build it."""
    found = prepared(target, flags)
    if found is not None:
        return found
    stream = stream if stream is not None else sys.stderr
    stream.write(f"crslab: preparing the WebAssembly compiler (zig's C library for {target}; once per "
                 "installation, 1 to 2 minutes)\n")
    stream.flush()
    done = threading.Event()
    start = time.monotonic()
    tty = stream.isatty()

    def tick() -> None:  # a running clock on a terminal, a line now and then elsewhere
        while not done.wait(1.0 if tty else PROGRESS_EVERY_S):
            took = time.monotonic() - start
            stream.write(f"\r  {took:4.0f} s" if tty else
                         f"crslab:   still building zig's C library: {took:.0f} s\n")
            stream.flush()

    clock = threading.Thread(target=tick, daemon=True)
    clock.start()
    try:
        with tempfile.TemporaryDirectory(prefix="crslab-zig-") as tmp:
            work = Path(tmp)
            src = work / "probe.c"
            src.write_text(PROBE)
            from crslab.lab.compile_process import run_compile

            env = zig_environment(work / "cache")
            env[ZIG_CACHE_ENV] = str(work / "global")  # only what is copied out is kept
            # built once (its messages are long), then linked again with -v, from zig's cache, to
            # read which files it links
            for verbose in ([], ["-v"]):
                r = run_compile([*zig_cc(), f"--target={target}", *flags, *verbose, str(src), "-o",
                                 str(work / "probe")], cwd=work, env=env, timeout_s=FIRST_USE_TIMEOUT_S,
                                cpu_s=int(FIRST_USE_TIMEOUT_S), memory_bytes=PREPARE_MEMORY_BYTES)
                if r.timed_out:
                    raise RuntimeError(f"zig did not finish building its C library for {target} within "
                                       f"{FIRST_USE_TIMEOUT_S:.0f} s")
                if r.returncode != 0:
                    first = next((line for line in r.stderr.splitlines() if "error" in line), "no message")
                    raise RuntimeError(f"zig cannot build its C library for {target}: {first}")
            includes, link = link_inputs(r.stderr, work)
            lib = (zig_dir() / "lib").resolve()
            inside = [str(Path(i).resolve().relative_to(lib)) for i in includes
                      if Path(i).resolve().is_relative_to(lib / "libc")]
            if not link or not inside:
                raise RuntimeError(f"zig's messages named no C library for {target} (zig {zig_version()})")
            libc = _keep(target, flags, inside, link)
    finally:
        done.set()
        clock.join()
        if tty:
            stream.write("\r")
    stream.write(f"crslab: the WebAssembly compiler is ready ({time.monotonic() - start:.0f} s, kept in "
                 f"{libc.folder.parent})\n")
    stream.flush()
    return libc


PROGRESS_EVERY_S = 10.0
"""How often a build of zig's C library says how long it has taken, where no terminal shows a clock."""


def _keep(target: str, flags: list[str], includes: list[str], link: list[Path]) -> LibC:
    """Copy the built library's objects into the first home that can be written, atomically."""
    problems = []
    for home in libc_homes():
        folder = home / libc_name(target, flags)
        try:
            home.mkdir(parents=True, exist_ok=True)
            part = Path(tempfile.mkdtemp(prefix=".part-", dir=home))
            part.chmod(0o755)  # every user of the installation reads it
            names = []
            digests = {}
            for i, path in enumerate(link):
                name = f"{i:02d}-{path.name}"
                data = path.read_bytes()
                (part / name).write_bytes(data)
                (part / name).chmod(0o644)
                names.append(name)
                digests[name] = hashlib.sha256(data).hexdigest()
            (part / "manifest.json").write_text(json.dumps({"zig": zig_version(), "target": target,
                                                            "flags": flags, "includes": includes,
                                                            "link": names, "sha256": digests}, indent=1))
            (part / "manifest.json").chmod(0o644)
            try:
                part.rename(folder)
            except OSError:  # another process kept one first
                shutil.rmtree(part, ignore_errors=True)
        except OSError as exc:
            problems.append(f"{home}: {exc.strerror}")
            continue
        found = prepared(target, flags)
        if found is not None:
            return found
    raise RuntimeError(f"zig's C library cannot be kept ({'; '.join(problems)})")

