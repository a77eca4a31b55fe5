"""The per-user cache: compiled labs and board objects (content-addressed), and crslab's runtime
files when the installed package is not a plain folder (a zip) and a compiler needs real paths.

Nothing is ever written into the installed package: the cache is the only place crslab writes to
on its own.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

CACHE_ENV = "CRSLAB_CACHE_DIR"


class CacheError(OSError):
    """The cache folder the user asked for cannot be used; the message names it."""


def cache_dir() -> Path:
    """Where builds are kept: ``$CRSLAB_CACHE_DIR``, else ``$XDG_CACHE_HOME/crslab`` (by default
    ``~/.cache/crslab``), else (a read-only home) a folder of this user's in the system's
    temporary directory.

    >>> import os, tempfile
    >>> os.environ[CACHE_ENV] = tempfile.mkdtemp()
    >>> cache_dir() == Path(os.environ.pop(CACHE_ENV))
    True
    """
    env = os.environ.get(CACHE_ENV)
    base = Path(env) if env else Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "crslab"
    try:
        base.mkdir(parents=True, exist_ok=True)
        if os.access(base, os.W_OK):
            return base
    except OSError:
        pass
    if env:
        raise CacheError(f"{CACHE_ENV}={env} cannot be created or written")
    fallback = Path(tempfile.gettempdir()) / f"crslab-cache-{os.getuid()}"
    fallback.mkdir(mode=0o700, parents=True, exist_ok=True)
    return fallback
