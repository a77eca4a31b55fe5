"""The per-user cache: compiled labs and board objects (content-addressed), wasmtime's compiled
firmware, zig's prepared C library when the installation cannot hold it, and crslab's runtime
files when the installed package is not a plain folder (a zip) and a compiler needs real paths.

Nothing is ever written into the installed package: the cache is the only place crslab writes to
on its own, and only its owner writes it. Every folder of it is checked when it is used (this
user's, a folder and not a symbolic link, written by nobody else: one its owner left open to its
group or others is made private, 0700, first): :func:`cache_dir` for the cache itself (a folder
named by ``$CRSLAB_CACHE_DIR`` or the fallback in the system's temporary folder that is not this
user's is refused with one line saying why), :func:`subfolder` for every folder in it.

What crslab loads from it as code (a build, a compiled firmware, zig's C library) is sealed: a
digest keyed by a secret of this user's (:func:`keyed_digest`), written beside the file, over the
very bytes written (:func:`write_sealed`: a private file, sealed, then renamed into place), checked
over the very bytes read (:func:`read_sealed`), so a file planted under a matching name, or
changed since, is refused.
"""

from __future__ import annotations

import hashlib
import hmac
import os
import secrets
import stat
import tempfile
from pathlib import Path

CACHE_ENV = "CRSLAB_CACHE_DIR"
KEY_FILE = "seal.key"
"""The per-user secret (32 random bytes, mode 0600) that keys the digests of sealed files."""
SEAL_SUFFIX = ".seal"
_CLOEXEC = getattr(os, "O_CLOEXEC", 0)


class CacheError(OSError):
    """The cache, or a folder or file of it, cannot be used; the message names it and says why."""


def unsafe_reason(folder: Path, *, follow: bool = True) -> str | None:
    """Why ``folder`` may not be this user's cache or a folder of it (another user owns it, it is a
    symbolic link where none is allowed, it is not a folder), else None. A folder of this user's
    that its group or others may write is made private (0700) here.

    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp()); d.chmod(0o770)
    >>> unsafe_reason(d), oct(d.stat().st_mode & 0o777)
    (None, '0o700')
    >>> link = d / "link"; link.symlink_to(d)
    >>> unsafe_reason(link, follow=False)
    'it is a symbolic link'
    """
    st = os.stat(folder) if follow else os.lstat(folder)
    if stat.S_ISLNK(st.st_mode):
        return "it is a symbolic link"
    if not stat.S_ISDIR(st.st_mode):
        return "it is not a folder"
    if st.st_uid != os.getuid():
        return f"it belongs to another user (uid {st.st_uid})"
    if st.st_mode & 0o022:
        os.chmod(folder, 0o700, follow_symlinks=follow)
    return None


def usable_problem(base: Path, *, follow: bool = True) -> str | None:
    """Create ``base`` (private) when missing; None when it is this user's and writable, else why not."""
    try:
        base.mkdir(mode=0o700, parents=True, exist_ok=True)
    except FileExistsError:  # a link to nowhere, a file: said below
        pass
    except OSError as exc:
        return f"it cannot be made ({exc.strerror or exc})"
    try:
        why = unsafe_reason(base, follow=follow)
    except OSError as exc:
        return f"it cannot be used ({exc.strerror or exc})"
    if why is None and not os.access(base, os.W_OK):
        why = "it cannot be written"
    return why


def fallback_dir() -> Path:
    """The cache of a user whose home cannot hold one: ``crslab-cache-UID`` in the system's
    temporary folder (one per user, always the same: it is either this user's, or refused)."""
    return Path(tempfile.gettempdir()) / f"crslab-cache-{os.getuid()}"


def cache_dir() -> Path:
    """Where builds are kept: ``$CRSLAB_CACHE_DIR``, else ``$XDG_CACHE_HOME/crslab`` (by default
    ``~/.cache/crslab``), else (a read-only home) :func:`fallback_dir`. Raises :class:`CacheError`,
    one line saying why, when none can be used (a folder another user made first, a link).

    >>> import os, tempfile
    >>> os.environ[CACHE_ENV] = tempfile.mkdtemp()
    >>> cache_dir() == Path(os.environ.pop(CACHE_ENV))
    True
    """
    env = os.environ.get(CACHE_ENV)
    base = Path(env) if env else Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "crslab"
    why = usable_problem(base)
    if why is None:
        return base
    if env:
        raise CacheError(f"{CACHE_ENV}={env} cannot be used as crslab's cache: {why}")
    fallback = fallback_dir()
    why_not = usable_problem(fallback, follow=False)
    if why_not is None:
        return fallback
    raise CacheError(f"crslab has no cache it can use: {base}: {why}; {fallback}: {why_not} (set {CACHE_ENV} "
                     "to a folder of yours)")


def subfolder(cache: Path, *names: str) -> Path:
    """The folder ``cache/names...``, each level made (private) when missing and checked as it is
    used (:func:`unsafe_reason`, never following a link); :class:`CacheError` names the first that
    cannot be used.

    >>> import tempfile
    >>> c = Path(tempfile.mkdtemp())
    >>> subfolder(c, "compiled") == c / "compiled"
    True
    >>> (c / "elsewhere").symlink_to(c); subfolder(c, "elsewhere")
    Traceback (most recent call last):
    ...
    crslab.cache.CacheError: .../elsewhere cannot be used in crslab's cache: it is a symbolic link (remove it)
    """
    folder = cache
    for name in names:
        folder = folder / name
        try:
            folder.mkdir(mode=0o700)
        except FileExistsError:
            pass
        except OSError as exc:
            raise CacheError(f"{folder} cannot be made in crslab's cache ({exc.strerror or exc})") from None
        try:
            why = unsafe_reason(folder, follow=False)
        except OSError as exc:
            why = exc.strerror or str(exc)
        if why is not None:
            raise CacheError(f"{folder} cannot be used in crslab's cache: {why} (remove it)")
    return folder


# -- the seal -------------------------------------------------------------------------------------

_keys: dict[tuple[Path, int, int], bytes] = {}


def _key(cache: Path) -> bytes:
    """This user's sealing secret in ``cache`` (made on first use; one that is not this user's
    alone is replaced, which unseals everything sealed with it); read once per process while the
    file stays the same."""
    path = cache / KEY_FILE
    try:
        st = os.lstat(path)
        known = _keys.get((path, st.st_ino, st.st_mtime_ns))
        if known is not None:
            return known
    except FileNotFoundError:
        pass
    key = _read_or_make_key(cache, path)
    try:
        st = os.lstat(path)
        _keys[(path, st.st_ino, st.st_mtime_ns)] = key
    except FileNotFoundError:
        pass
    return key


def _read_or_make_key(cache: Path, path: Path) -> bytes:
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | _CLOEXEC)
        with os.fdopen(fd, "rb") as f:
            st = os.fstat(f.fileno())
            key = f.read(64)
        if st.st_uid == os.getuid() and not st.st_mode & 0o077 and len(key) == 32:
            return key
        path.unlink()
    except FileNotFoundError:
        pass
    except OSError:  # a link, or unreadable: replaced
        path.unlink(missing_ok=True)
    key = secrets.token_bytes(32)
    tmp = cache / f"{KEY_FILE}.{os.getpid()}.{secrets.token_hex(4)}"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | _CLOEXEC, 0o600)
    with os.fdopen(fd, "wb") as f:
        f.write(key)
    try:
        os.link(tmp, path)  # the first writer's key wins; a second one reads it
    except FileExistsError:
        tmp.unlink()
        return _read_or_make_key(cache, path)
    tmp.unlink()
    return key


def keyed_digest(data: bytes, cache: Path | None = None) -> str:
    """The digest of ``data`` keyed by this user's secret (HMAC-SHA256): nobody without the key
    file (0600, in the cache) can make one that matches."""
    return hmac.new(_key(cache if cache is not None else cache_dir()), data, hashlib.sha256).hexdigest()


def _seal_of(name: str, data: bytes, cache: Path | None) -> str:
    return keyed_digest(name.encode() + b"\0" + data, cache)


def read_own(path: Path, *, owners: tuple[int, ...] = ()) -> bytes | None:
    """The bytes of ``path`` when it is a regular file (not a link) of this user's (or of one of
    ``owners``) that nobody else may write, read through the one descriptor checked; else None.

    >>> import tempfile
    >>> f = Path(tempfile.mkdtemp()) / "x"; _ = f.write_bytes(b"mine"); f.chmod(0o644)
    >>> read_own(f), (f.chmod(0o664), read_own(f))[1]
    (b'mine', None)
    """
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | _CLOEXEC)
    except OSError:
        return None
    with os.fdopen(fd, "rb") as f:
        st = os.fstat(f.fileno())
        if (not stat.S_ISREG(st.st_mode) or st.st_uid not in (os.getuid(), *owners)
                or st.st_mode & 0o022):
            return None
        try:
            return f.read()
        except OSError:
            return None


def read_sealed(path: Path, cache: Path | None = None) -> bytes | None:
    """The bytes of ``path`` when this user's build sealed these very bytes under this name
    (:func:`write_sealed`): a file of another user's, a link, one others may write, one planted or
    changed since, is None.

    >>> import tempfile
    >>> c = Path(tempfile.mkdtemp()); f = c / "lab.wasm"; _ = f.write_bytes(b"module")
    >>> read_sealed(f, c), (write_sealed(f, b"module", c), read_sealed(f, c))[1]
    (None, b'module')
    >>> _ = f.write_bytes(b"planted"); read_sealed(f, c)
    """
    data = read_own(path)
    expected = read_own(path.with_name(path.name + SEAL_SUFFIX))
    if data is None or expected is None:
        return None
    try:
        ok = hmac.compare_digest(expected.decode("ascii"), _seal_of(path.name, data, cache))
    except UnicodeDecodeError:
        return None
    return data if ok else None


def is_sealed(path: Path, cache: Path | None = None) -> bool:
    """Whether ``path`` holds what this user's build sealed (see :func:`read_sealed`): for a file
    handed on by its path (a compiler's input, a shared object), checked when it is used; it lies
    in a folder only this user writes (:func:`subfolder`), so what was checked is what is read."""
    return read_sealed(path, cache) is not None


def private_file(folder: Path, name: str) -> tuple[int, Path]:
    """A new private file (0600, made here: never one that was there, never through a link) in
    ``folder``, named after ``name``: its descriptor (open for reading and writing) and path."""
    part = folder / f".{name}.{os.getpid()}.{secrets.token_hex(4)}.part"
    fd = os.open(part, os.O_RDWR | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | _CLOEXEC, 0o600)
    return fd, part


def seal_into_place(part: Path, target: Path, data: bytes, cache: Path | None = None) -> None:
    """Seal ``data``, the bytes of the private file ``part`` (:func:`private_file`), under
    ``target``'s name, then rename ``part`` to ``target``: the seal covers exactly what lies there."""
    fd, seal_part = private_file(target.parent, target.name + SEAL_SUFFIX)
    with os.fdopen(fd, "wb") as f:
        f.write(_seal_of(target.name, data, cache).encode("ascii"))
    os.replace(seal_part, target.with_name(target.name + SEAL_SUFFIX))
    os.replace(part, target)


def write_sealed(target: Path, data: bytes, cache: Path | None = None) -> None:
    """Write ``data`` to ``target`` (in a folder of the cache): a private file, sealed, then renamed
    into place (see :func:`seal_into_place`)."""
    fd, part = private_file(target.parent, target.name)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        seal_into_place(part, target, data, cache)
    finally:
        part.unlink(missing_ok=True)


def seal_file(made: Path, target: Path, cache: Path | None = None) -> None:
    """Keep the file ``made`` (a compiler's output) as ``target``, sealed: its bytes copied into a
    private file there, so that what is sealed is what lies at ``target``."""
    write_sealed(target, made.read_bytes(), cache)
