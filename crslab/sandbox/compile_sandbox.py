"""The sandbox a lab file is compiled in: the compiler (gcc or clang, and the programs it runs:
preprocessor, compiler proper, assembler, linker) may read the lab's own folder, crslab's
headers and objects, and the system's compiler headers, programs and libraries, and may write
only the build folder. So ``#include "/home/ta/.ssh/id_rsa"`` (or a symbolic link in the lab's
folder that points out of it, or an assembler ``.incbin``) fails with "Permission denied" and
never puts a byte of that file into an error message, a build or a report.

Landlock alone does this (it is inherited by every program the compiler starts, and also
refuses TCP and signals to other processes). It is prepared in the crslab process; the
compiler's child process only has to call ``landlock_restrict_self`` before ``exec``.

>>> forbidden_read("lab.c:3:10: fatal error: /home/ta/key.h: Permission denied\\n")
'/home/ta/key.h'
>>> forbidden_read("lab.c:3:10: fatal error: cannot open file '/home/ta/key.h': Permission denied\\n")
'/home/ta/key.h'
>>> forbidden_read("lab.c:3:10: fatal error: nope.h: No such file or directory\\n") is None
True
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from crslab.sandbox import landlock
from crslab.sandbox.landlock import READ, RUN, WRITE_TREE

SYSTEM_RUN_DIRS = ("/usr/bin", "/bin", "/usr/libexec", "/usr/lib", "/usr/lib64", "/usr/lib32", "/lib",
                   "/lib64", "/lib32", "/usr/local/bin", "/usr/local/lib", "/usr/local/libexec")
"""Programs and libraries a compiler driver runs and links with."""
SYSTEM_READ_PATHS = ("/usr/include", "/usr/local/include", "/etc/ld.so.cache", "/etc/ld.so.conf",
                     "/etc/ld.so.conf.d")
"""Headers, and what the dynamic loader and the linker read to find libraries."""

_REFUSED = (re.compile(r"cannot open file '(.+?)': Permission denied"),  # clang, #include
            re.compile(r"(?:fatal )?error: (.+?): Permission denied"),   # gcc, #include
            re.compile(r"can't open (.+?) for reading: Permission denied"),  # the assembler's .incbin
            re.compile(r"cannot open (.+?): Permission denied"))             # the linker


def forbidden_read(diagnostics: str) -> str | None:
    """The file a sandboxed compiler was refused, from its messages (None if there is none)."""
    for line in diagnostics.splitlines():
        for pattern in _REFUSED:
            m = pattern.search(line)
            if m:
                return m.group(1).strip("'\"‘’")
    return None


def include_search_dirs(verbose: str) -> list[str]:
    """The folders a C compiler searches for ``<...>`` headers, as its ``-v`` messages list them
    (gcc's and clang's, zig's clang included).

    >>> include_search_dirs("#include <...> search starts here:\\n /usr/include\\nEnd of search list.\\n")
    ['/usr/include']
    """
    found: list[str] = []
    inside = False
    for line in verbose.splitlines():
        if line.startswith("#include <...> search starts here"):
            inside = True
        elif line.startswith("End of search list"):
            inside = False
        elif inside:
            found.append(line.strip())
    return found


@cache
def compiler_dirs(compiler: tuple[str, ...]) -> tuple[str, ...]:
    """Where the compiler (its command, e.g. ``("gcc",)`` or ``("ccache", "clang")``) lives and
    searches for its programs, headers and libraries (so a compiler installed outside /usr, e.g.
    in a conda environment, works too)."""
    found: list[str] = []
    for program in compiler:
        exe = shutil.which(program)
        if exe is None:
            continue
        for p in (exe, os.path.realpath(exe)):
            found.append(str(Path(p).parent))
            found.append(str(Path(p).parent.parent / "lib"))
            found.append(str(Path(p).parent.parent / "libexec"))
    try:
        dirs = subprocess.run([*compiler, "-print-search-dirs"], capture_output=True, text=True,
                              timeout=30).stdout
        for line in dirs.splitlines():
            _, _, value = line.partition(": ")
            found += [d for d in value.lstrip("=").split(":") if d]
        found += include_search_dirs(subprocess.run([*compiler, "-E", "-v", "-x", "c", os.devnull],
                                                    capture_output=True, text=True, timeout=30).stderr)
    except (OSError, subprocess.SubprocessError):
        pass
    out: list[str] = []
    for d in found:
        real = os.path.realpath(d)
        if os.path.isdir(real) and real not in out:
            out.append(real)
    return tuple(out)


@dataclass
class CompilerSandbox:
    """What one compiler run may read and write; :meth:`preexec` gives the function the
    compiler's child process calls before ``exec``."""

    read: tuple[Path, ...]
    write: Path
    compiler: tuple[str, ...] = ("gcc",)
    run: tuple[Path, ...] = ()
    """Folders of programs and libraries it runs beyond the system's and the compiler's own (zig's)."""
    cache: tuple[Path, ...] = ()
    """Folders the compiler keeps its own cache in and must write (zig's: it writes its manifests
    there at every run; the lab's code cannot choose what goes there)."""

    def ruleset(self) -> landlock.Ruleset:
        """The Landlock ruleset (its descriptor must reach the child: ``pass_fds``)."""
        rs = landlock.Ruleset()
        own = compiler_dirs(self.compiler) if self.compiler else ()
        for d in (*SYSTEM_RUN_DIRS, *own, *self.run):
            rs.allow(d, RUN)
        for p in (*SYSTEM_READ_PATHS, *self.read):
            rs.allow(p, READ)
        rs.allow(self.write, READ | WRITE_TREE)
        for d in self.cache:
            rs.allow(d, READ | WRITE_TREE)
        rs.allow(os.devnull, landlock.READ_FILE | landlock.WRITE_FILE)
        return rs

    @staticmethod
    def preexec(ruleset_fd: int) -> Callable[[], None]:
        """The child's last step before ``exec``: two system calls, nothing that allocates."""
        def restrict() -> None:
            landlock.set_no_new_privs()
            landlock.restrict_fd(ruleset_fd)
        return restrict

    def environment(self) -> dict[str, str]:
        """The compiler's environment: temporary files go into the build folder."""
        env = dict(os.environ)
        for key in ("TMPDIR", "TMP", "TEMP"):
            env[key] = str(self.write)
        return env


def compiler_sandbox(lab_paths: Iterable[Path], build_dir: Path, extra_read: Iterable[Path] = (),
                     compiler: Sequence[str] | str = ("gcc",), run_dirs: Iterable[Path] = (),
                     cache_dirs: Iterable[Path] = ()) -> CompilerSandbox:
    """The sandbox for compiling a lab: ``lab_paths`` are the lab's own file(s), whose folders
    (as named and as resolved) may be read; ``extra_read`` crslab's headers and objects;
    ``compiler`` the command that runs the compiler (empty: none beyond ``run_dirs``, the folders
    of a compiler that brings its own, such as zig)."""
    read: list[Path] = []
    for p in lab_paths:
        for folder in (Path(p).absolute().parent, Path(p).resolve().parent):
            if folder not in read:
                read.append(folder)
    read += [Path(p) for p in extra_read]
    command = (compiler,) if isinstance(compiler, str) else tuple(compiler)
    return CompilerSandbox(tuple(read), Path(build_dir), command, tuple(Path(d) for d in run_dirs),
                           tuple(Path(d) for d in cache_dirs))
