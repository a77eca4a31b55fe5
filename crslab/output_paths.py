"""Every file or folder crslab writes is made where the user named it, folders included:
``crslab record --lab lab1.c -o golden/lab1_tour.txt`` works in a repository with no ``golden/``
yet. Writers call :func:`with_parent` on the path first; a folder that cannot be made raises
``OSError`` as the write itself would, and the caller turns it into its one-line error.

>>> import tempfile
>>> base = Path(tempfile.mkdtemp())
>>> with_parent(base / "golden" / "lab1_tour.txt").parent.is_dir()
True
>>> with_parent("plain.txt")
PosixPath('plain.txt')
"""

from __future__ import annotations

import os
from pathlib import Path


def with_parent(path: str | os.PathLike[str]) -> Path:
    """``path``, its folder (and the folders above it) made if missing."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    return target


def ready_to_write(path: str | os.PathLike[str]) -> Path:
    """``path`` with its folder made, checked before a long computation whose result goes there: a
    folder that cannot be made, or cannot be written into, raises ``OSError`` now, not once the
    work is done.

    >>> import tempfile
    >>> ready_to_write(Path(tempfile.mkdtemp()) / "fric" / "table.toml").parent.is_dir()
    True
    """
    import errno

    target = Path(path)
    above = next((f for f in target.parents if f.exists() or f.is_symlink()), None)
    if above is not None and not above.is_dir():
        raise NotADirectoryError(errno.ENOTDIR, f"{above.name} is a file, not a folder", str(above))
    target = with_parent(path)
    if not os.access(target.parent, os.W_OK | os.X_OK):
        raise OSError(errno.EACCES, os.strerror(errno.EACCES), str(target.parent))
    return target


def folder(path: str | os.PathLike[str]) -> Path:
    """The folder ``path``, made (with the folders above it) if missing."""
    target = Path(path)
    target.mkdir(parents=True, exist_ok=True)
    return target
