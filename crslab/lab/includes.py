"""What a lab file includes from its own folder, checked before a compiler opens it.

A FIFO (or a socket, or a device node) in the lab's folder named by an ``#include`` would make
the compiler wait or read forever: the compile sandbox lets the compiler read the lab's folder,
and opening a FIFO blocks until somebody writes to it. So every ``#include "..."`` and
``#include <...>`` that names something inside the lab's folder is looked at first, in the lab
file and, recursively, in the files it includes from there; one that is not a regular file stops
the build with its line. Names outside the folder are left to the compiler and its sandbox (which
refuses them without saying what they are), and an include whose name a macro builds still meets
the compiler's time limit (:mod:`crslab.lab.compile_process`).

The same headers hold what a team keeps out of its lab file: its globals, watched ones and its
encoder offsets among them (:func:`own_variables`, :func:`with_own_headers`).

>>> import tempfile
>>> folder = Path(tempfile.mkdtemp())
>>> os.mkfifo(folder / "gains.h")
>>> _ = (folder / "lab.c").write_text('#include "math.h"\\n#include "gains.h"\\n')
>>> local_includes(folder / "lab.c")[0]
'lab.c:2 includes gains.h, which is a FIFO, not a file'
>>> _ = (folder / "lab.c").write_text('#include "math.h"\\n')
>>> local_includes(folder / "lab.c")[0] is None
True
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path

from crslab.lab.variables import LabVariable, variables_of_files

INCLUDE = re.compile(rb'^[ \t]*#[ \t]*include[ \t]*(?:"([^"\n]+)"|<([^>\n]+)>)', re.MULTILINE)
MAX_FILES = 200
"""How many files of the lab's folder are followed (a lab includes a few headers at most)."""
MAX_BYTES = 4 * 1024 * 1024
"""How much of each is read."""
MAX_TOTAL_BYTES = 32 * 1024 * 1024
"""How much of them is read in all (:func:`header_texts`)."""

_KINDS = ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISSOCK, "a socket"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"))


def _kind(mode: int) -> str | None:
    """What a file that is neither a regular file nor a folder is, else None."""
    return next((name for test, name in _KINDS if test(mode)), None)


def _inside(path: Path, folder: Path) -> bool:
    return path == folder or folder in path.parents


def local_includes(lab: Path) -> tuple[str | None, list[Path]]:
    """The first ``#include`` reachable from ``lab`` that names something in the lab's folder that
    is not a regular file (``"FILE:LINE includes NAME, which is a FIFO, not a file"``, else None),
    and the regular files of the lab's folder that ``lab`` includes, directly or through them
    (resolved; the lab itself not among them): a build is named by their contents too, so an edited
    header builds anew.

    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> _ = (folder / "gains.h").write_text("#define KP 10\\n")
    >>> _ = (folder / "lab.c").write_text('#include <math.h>\\n#include "gains.h"\\n')
    >>> [p.name for p in local_includes(folder / "lab.c")[1]]
    ['gains.h']
    """
    start = lab.resolve()
    folder = start.parent
    seen: set[Path] = set()
    todo = [start]
    while todo and len(seen) < MAX_FILES:
        current = todo.pop()
        if current in seen:
            continue
        seen.add(current)
        try:
            with open(current, "rb") as f:
                text = f.read(MAX_BYTES)
        except OSError:
            continue
        for m in INCLUDE.finditer(text):
            name = (m.group(1) or m.group(2)).decode("utf-8", "replace")
            for base in dict.fromkeys((current.parent, folder)):
                candidate = Path(os.path.normpath(base / name))
                if not _inside(candidate, folder):
                    continue
                try:
                    resolved = candidate.resolve()
                    mode = os.stat(resolved).st_mode if _inside(resolved, folder) else None
                except (OSError, RuntimeError):
                    continue
                if mode is None:
                    continue
                kind = _kind(mode)
                if kind is not None:
                    line = text.count(b"\n", 0, m.start()) + 1
                    where = current.relative_to(folder) if _inside(current, folder) else current.name
                    return f"{where}:{line} includes {name}, which is {kind}, not a file", []
                if stat.S_ISREG(mode):
                    todo.append(resolved)
                    break
    return None, sorted(seen - {start})


def header_texts(lab: Path, headers: list[Path] | None = None) -> list[tuple[str, str]]:
    """The lab's own headers (``headers``, default :func:`local_includes`'s) as (name from the
    lab's folder, text), each read up to :data:`MAX_BYTES` and all up to :data:`MAX_TOTAL_BYTES`,
    as much as a build's private copy holds (a folder of huge headers is not read whole); one that
    cannot be read is empty (the compiler then says so).

    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> _ = (folder / "gains.h").write_text("#define KP 10\\n")
    >>> _ = (folder / "lab.c").write_text('#include "gains.h"\\n')
    >>> header_texts(folder / "lab.c")
    [('gains.h', '#define KP 10\\n')]
    """
    folder = lab.resolve().parent
    left, out = MAX_TOTAL_BYTES, []
    for header in local_includes(lab)[1] if headers is None else headers:
        try:
            with open(header, "rb") as f:
                data = f.read(min(MAX_BYTES, left))
        except OSError:
            data = b""
        left -= len(data)
        out.append((header.relative_to(folder).as_posix(), data.decode("utf-8", "replace")))
    return out


def with_own_headers(lab: Path, text: str) -> str:
    """The text of the files of the lab's folder that ``lab`` includes (its own headers,
    :func:`header_texts`), then ``text`` (the lab's own): all its file-scope definitions, where a
    team keeps some in a header of its own (its encoder offsets, :mod:`crslab.contest.offsets`).

    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> _ = (folder / "bench.h").write_text("float offset_Enc2_rad = -0.41;\\n")
    >>> text = '#include "bench.h"\\nlong mycount = 0;\\n'
    >>> _ = (folder / "final.c").write_text(text)
    >>> print(with_own_headers(folder / "final.c", text))
    float offset_Enc2_rad = -0.41;
    <BLANKLINE>
    #include "bench.h"
    long mycount = 0;
    <BLANKLINE>
    """
    return "\n".join([*(t for _, t in header_texts(lab)), text])


def own_variables(lab: Path, text: str, headers: list[Path] | None = None) -> list[LabVariable]:
    """The variables of the lab file ``lab`` (its ``text``) and of the headers of its folder it
    includes (:func:`header_texts`; ``headers`` when its caller found them already), the headers
    read first: a team may keep its globals, watched ones and its encoder offsets among them, in a
    header of its own (``file`` names it, from the lab's folder).

    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> _ = (folder / "globals.h").write_text('#pragma DATA_SECTION(mode, ".my_vars")\\nint mode = 1;\\n')
    >>> text = '#include "globals.h"\\nfloat gain = 2;\\n'
    >>> _ = (folder / "lab.c").write_text(text)
    >>> [(v.name, v.file, v.line, v.section) for v in own_variables(folder / "lab.c", text)]
    [('mode', 'globals.h', 2, '.my_vars'), ('gain', '', 2, None)]
    """
    return variables_of_files([*header_texts(lab, headers), ("", text)])
