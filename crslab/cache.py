"""The per-user cache: compiled labs and board objects (content-addressed), and crslab's runtime
files when the installed package is not a plain folder (a zip) and a compiler needs real paths.

Nothing is ever written into the installed package: the cache is the only place crslab writes to
on its own. Only its owner writes it: a cache folder another user owns is refused (a folder named
by ``$CRSLAB_CACHE_DIR``: with one line saying why) or passed over for a fresh private one (the
fallback in the system's temporary folder, where anyone may have made a folder of that name
first), and one its owner left writable by the group or others is made private (0700) before it
is used. What crslab loads from it as code (a build, a compiled firmware) is sealed: a digest keyed
by a secret of this user's (:func:`seal`, :func:`is_sealed`), so a file planted under a matching
name is refused.
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


class CacheError(OSError):
    """The cache folder the user asked for cannot be used; the message names it."""


def unsafe_reason(folder: Path, *, follow: bool = True) -> str | None:
    """Why ``folder`` may not be this user's cache (another user owns it, it is a symbolic link
    where none is allowed, it is not a folder), else None. A folder of this user's that its group
    or others may write is made private (0700) here.

    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp()); d.chmod(0o777)
    >>> unsafe_reason(d), oct(d.stat().st_mode & 0o777)
    (None, '0o700')
    """
    st = os.stat(folder) if follow else os.lstat(folder)
    if stat.S_ISLNK(st.st_mode):
        return "it is a symbolic link"
    if not stat.S_ISDIR(st.st_mode):
        return "it is not a folder"
    if st.st_uid != os.getuid():
        return f"it belongs to another user (uid {st.st_uid})"
    if st.st_mode & 0o022:
        os.chmod(folder, 0o700)
    return None


def _usable(base: Path, *, follow: bool = True) -> str | None:
    """Create ``base`` (private) when missing; None when it is this user's and writable, else why not."""
    try:
        base.mkdir(mode=0o700, parents=True, exist_ok=True)
        why = unsafe_reason(base, follow=follow)
    except OSError as exc:
        return exc.strerror or str(exc)
    if why is None and not os.access(base, os.W_OK):
        why = "it cannot be written"
    return why


def cache_dir() -> Path:
    """Where builds are kept: ``$CRSLAB_CACHE_DIR``, else ``$XDG_CACHE_HOME/crslab`` (by default
    ``~/.cache/crslab``), else (a read-only home) ``crslab-cache-UID`` in the system's temporary
    folder, else (that one another user's) a fresh private folder there.

    >>> import os, tempfile
    >>> os.environ[CACHE_ENV] = tempfile.mkdtemp()
    >>> cache_dir() == Path(os.environ.pop(CACHE_ENV))
    True
    """
    env = os.environ.get(CACHE_ENV)
    base = Path(env) if env else Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "crslab"
    why = _usable(base)
    if why is None:
        return base
    if env:
        raise CacheError(f"{CACHE_ENV}={env} cannot be used as crslab's cache: {why}")
    fallback = Path(tempfile.gettempdir()) / f"crslab-cache-{os.getuid()}"
    if _usable(fallback, follow=False) is None:
        return fallback
    return Path(tempfile.mkdtemp(prefix=f"crslab-cache-{os.getuid()}-"))


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
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW)
        with os.fdopen(fd, "rb") as f:
            st = os.fstat(f.fileno())
            key = f.read(64)
        if st.st_uid == os.getuid() and not st.st_mode & 0o077 and len(key) == 32:
            return key
        path.unlink()
    except FileNotFoundError:
        pass
    key = secrets.token_bytes(32)
    tmp = cache / f"{KEY_FILE}.{os.getpid()}.{secrets.token_hex(4)}"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
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


def seal(path: Path, cache: Path | None = None) -> None:
    """Record, beside ``path`` (``NAME.seal``), its keyed digest (of its name and its bytes: this
    user's build wrote it, under this name)."""
    digest = keyed_digest(path.name.encode() + b"\0" + path.read_bytes(), cache)
    tmp = path.with_name(f"{path.name}{SEAL_SUFFIX}.{os.getpid()}.tmp")
    tmp.write_text(digest)
    tmp.replace(path.with_name(path.name + SEAL_SUFFIX))


def is_sealed(path: Path, cache: Path | None = None) -> bool:
    """Whether ``path`` holds what this user's build sealed (a file planted under its name, or one
    changed since, is not).

    >>> import os, tempfile
    >>> c = Path(tempfile.mkdtemp()); f = c / "lab.wasm"; _ = f.write_bytes(b"module")
    >>> is_sealed(f, c), (seal(f, c), is_sealed(f, c))[1]
    (False, True)
    >>> _ = f.write_bytes(b"planted"); is_sealed(f, c)
    False
    """
    try:
        expected = path.with_name(path.name + SEAL_SUFFIX).read_text()
        data = path.read_bytes()
    except (OSError, UnicodeDecodeError):
        return False
    return hmac.compare_digest(expected, keyed_digest(path.name.encode() + b"\0" + data, cache))
