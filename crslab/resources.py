"""Where crslab's runtime files are, found through :mod:`importlib.resources`.

Six folders travel with the package:

- ``csrc``: the C that labs are compiled against (the firmware's stand-ins ``firmware`` and their
  headers ``firmware/include``, the emulated board ``board``, the plant's C ``plant``, what the
  board and the firmware share ``port``, the kinematics core ``kin``) and crslab's own labs (``labs``);
- ``models``: the MuJoCo models (``models/crs_arm``);
- ``scenarios``: the built-in scenarios (``crslab/scenario/builtin``); ``robots``: the course robots' files;
  ``worlds``: the built-in worlds (``crslab/worlds``);
- ``octave``: the files that let GNU Octave run the course's MATLAB scripts (``crslab/host_tools/octave``).

``csrc`` and ``models`` live at the top of the repository. The build (``setup.py``) copies them
into the wheel as ``crslab/_data/csrc`` and ``crslab/_data/models``; an editable install in a
checkout has no ``_data`` and uses the checkout's own folders, so an edit to ``csrc/board/board_io.c``
counts at the next run. ``scenarios``, ``robots`` and ``octave`` are ordinary package data.

A compiler and MuJoCo need real file-system paths. When the package is a plain folder (any
``pip install``) :func:`path` is the file itself; when it is not (imported from a zip), the
folder is extracted once into the per-user cache (:func:`crslab.cache.cache_dir`), under a name
that changes with its content. (``importlib.resources.as_file`` would give a copy that is
removed when its ``with`` block ends; a compiled lab and the MuJoCo model need theirs for the
whole run, and again at the next one.)

>>> (path("csrc", "board") / "board.h").is_file()
True
>>> sorted(p.name for p in path("models", "crs_arm").glob("*.xml"))
['crs_arm.xml', 'scene.xml']
"""

from __future__ import annotations

import hashlib
import os
import shutil
import tempfile
from functools import cache
from importlib.resources import files
from importlib.resources.abc import Traversable
from pathlib import Path

from crslab.cache import CacheError, cache_dir, read_own, subfolder, unsafe_reason

PACKAGED = "_data"
"""Sub-folder of the installed package that holds ``csrc`` and ``models`` (setup.py puts them there)."""
TOP_LEVEL = ("csrc", "models")
"""Folders kept at the top of the repository and mapped into the package by the build."""
IN_PACKAGE = {"scenarios": ("scenario", "builtin"), "robots": ("robots",), "octave": ("host_tools", "octave"),
              "worlds": ("worlds",)}
"""Folders that are package data in ``crslab/`` itself, and where."""


class ResourceError(FileNotFoundError):
    """A runtime folder is missing from the installation; the message says how to repair it."""


def folder(name: str) -> Traversable:
    """The ``csrc``, ``models``, ``scenarios``, ``robots`` or ``octave`` folder as installed (maybe in
    a zip)."""
    package = files("crslab")
    if name in IN_PACKAGE:
        return package.joinpath(*IN_PACKAGE[name])
    if name not in TOP_LEVEL:
        raise ValueError(f"no runtime folder named {name!r} (known: {', '.join((*TOP_LEVEL, *IN_PACKAGE))})")
    packaged = package / PACKAGED / name
    if packaged.is_dir():
        return packaged
    checkout = Path(__file__).resolve().parent.parent / name  # editable install in a checkout
    if checkout.is_dir() and (checkout.parent / "pyproject.toml").is_file():
        return checkout
    raise ResourceError(f"crslab's {name} folder is missing from its installation ({package}); "
                        "reinstall it: pip install --force-reinstall crslab")


def path(name: str, *parts: str) -> Path:
    """A real file-system path to ``name/parts...`` (a file or a folder), for a compiler or MuJoCo.

    >>> path("csrc", "labs", "lab1_kinematics.c").name
    'lab1_kinematics.c'
    """
    return _real_folder(name).joinpath(*parts)


@cache
def _real_folder(name: str) -> Path:
    return real_path(folder(name))


def real_path(resource: Traversable) -> Path:
    """``resource`` itself when it is a plain file or folder; else (a zip member) a copy of it in
    the per-user cache, made once per content.

    >>> import io, zipfile
    >>> buf = io.BytesIO()
    >>> with zipfile.ZipFile(buf, "w") as z:
    ...     z.writestr("pkg/inc/a.h", "#define A 1\\n")
    >>> copy = real_path(zipfile.Path(zipfile.ZipFile(buf), "pkg/inc/"))
    >>> (copy / "a.h").read_text()
    '#define A 1\\n'
    """
    if isinstance(resource, Path):
        return resource
    if resource.is_file():
        return _store({resource.name: resource.read_bytes()}, resource.name) / resource.name
    return _store(dict(_walk(resource, "")), resource.name)


def _walk(node: Traversable, prefix: str) -> list[tuple[str, bytes]]:
    out = []
    for child in node.iterdir():
        rel = f"{prefix}{child.name}"
        if child.is_dir():
            out.extend(_walk(child, rel + "/"))
        else:
            out.append((rel, child.read_bytes()))
    return out


def _store(contents: dict[str, bytes], name: str) -> Path:
    """Write ``contents`` (relative path -> bytes) under the cache, once; returns its folder. A
    compiler reads these files (crslab's headers): one kept from before is used only when it is
    this user's, no link, and holds exactly ``contents``."""
    h = hashlib.sha256()
    for rel in sorted(contents):
        h.update(rel.encode() + b"\0" + len(contents[rel]).to_bytes(8, "little") + contents[rel])
    home = subfolder(cache_dir(), "resources")
    target = home / f"{name.strip('/') or 'root'}-{h.hexdigest()[:20]}"
    if os.path.lexists(target):
        if unsafe_reason(target, follow=False) is None and all(
                read_own(target / rel) == data for rel, data in contents.items()):
            return target
        try:  # planted, or changed since: made again
            if target.is_symlink() or not target.is_dir():
                target.unlink()
            else:
                shutil.rmtree(target)
        except OSError as exc:
            raise CacheError(f"{target} cannot be used in crslab's cache and cannot be removed "
                             f"({exc.strerror}): remove it") from None
    staging = Path(tempfile.mkdtemp(prefix=".extract-", dir=home))
    for rel, data in contents.items():
        dest = staging / rel
        dest.parent.mkdir(parents=True, exist_ok=True)
        dest.write_bytes(data)
    try:
        os.rename(staging, target)  # atomic: another process may have won the race
    except OSError:
        shutil.rmtree(staging, ignore_errors=True)
    return target
