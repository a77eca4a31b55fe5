"""The host C compiler that labs are built with: ``$CC`` when set, else ``cc``, then ``gcc``, then
``clang``. gcc and clang take the same flags here; what differs (the AddressSanitizer runtime to
preload, how a shared object links to it) is asked of :class:`Compiler`.

>>> c = find_compiler({"CC": "gcc", "PATH": os.environ["PATH"]})
>>> c.family, c.command, c.argv == (shutil.which("gcc"),)
('gcc', ('gcc',), True)
"""

from __future__ import annotations

import os
import platform
import re
import shlex
import shutil
import subprocess
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache

DEFAULT_CANDIDATES = ("cc", "gcc", "clang")
INSTALL_HINT = ("install one: 'sudo apt install gcc' (Debian, Ubuntu, WSL), 'sudo dnf install gcc' (Fedora), "
                "or set CC to a C compiler")
VERSION_TIMEOUT_S = 20.0


class CompilerMissing(FileNotFoundError):
    """No usable C compiler; the message is one line saying how to get one."""


@dataclass(frozen=True)
class Compiler:
    """A C compiler: the command as given (``$CC`` split like a shell does), the program it found
    on PATH, the arguments that run it (``argv``), its family and its version.

    ``identity`` (the resolved program and everything ``--version`` printed) goes into the build
    cache's key, so a lab built by gcc is never reused by clang, nor across compiler upgrades.
    """

    command: tuple[str, ...]
    path: str
    argv: tuple[str, ...]
    family: str
    version: str
    identity: str

    @property
    def name(self) -> str:
        """How the compiler is called, as the user would type it."""
        return " ".join(self.command)

    def describe(self) -> str:
        """One line for messages: the command, the family and version, the program.

        >>> Compiler(("cc",), "/usr/bin/cc", ("/usr/bin/cc",), "gcc", "12.2.0", "").describe()
        'cc (gcc 12.2.0, /usr/bin/cc)'
        """
        return f"{self.name} ({self.family} {self.version}, {self.path})"

    def asan_runtime(self) -> str:
        """The AddressSanitizer runtime a sanitized lab's worker must preload (a path)."""
        name = "libasan.so" if self.family == "gcc" else f"libclang_rt.asan-{platform.machine()}.so"
        r = subprocess.run([*self.argv, f"-print-file-name={name}"], capture_output=True, text=True,
                           timeout=VERSION_TIMEOUT_S)
        return r.stdout.strip()

    def sanitizer_link_flags(self) -> list[str]:
        """Link flags of a sanitized shared object: clang must be told to use the shared runtime."""
        flags = ["-fsanitize=address,undefined"]
        return flags + (["-shared-libasan"] if self.family == "clang" else [])


def family_of(version_text: str) -> str:
    """``clang`` or ``gcc`` from what ``--version`` printed (anything else is treated as gcc).

    >>> family_of("Debian clang version 14.0.6")
    'clang'
    >>> family_of("cc (Debian 12.2.0-14) 12.2.0\\nCopyright (C) 2022 Free Software Foundation, Inc.")
    'gcc'
    """
    return "clang" if "clang" in version_text.splitlines()[0].lower() else "gcc"


def version_of(version_text: str) -> str:
    """The version number in the first line of ``--version``.

    >>> version_of("Debian clang version 14.0.6")
    '14.0.6'
    >>> version_of("gcc (Debian 12.2.0-14+deb12u1) 12.2.0")
    '12.2.0'
    """
    words = [w for w in version_text.splitlines()[0].split() if w[:1].isdigit() and "." in w]
    return words[-1] if words else "unknown version"


def find_compiler(environ: Mapping[str, str] | None = None) -> Compiler:
    """The compiler labs are built with (see the module); raises :class:`CompilerMissing`."""
    env = os.environ if environ is None else environ
    return _find(env.get("CC", "").strip(), env.get("PATH", os.defpath))


def _find(cc: str, search_path: str) -> Compiler:
    if cc:
        command = tuple(shlex.split(cc))
        program = shutil.which(command[0], path=search_path)
        if program is None:
            raise CompilerMissing(f"CC={cc}: {command[0]} was not found on PATH; {INSTALL_HINT}")
        return _probe(command, program, f"CC={cc}")
    for name in DEFAULT_CANDIDATES:
        program = shutil.which(name, path=search_path)
        if program is not None:
            return _probe((name,), program, name)
    raise CompilerMissing(f"no C compiler on PATH (tried {', '.join(DEFAULT_CANDIDATES)}); {INSTALL_HINT}")


def _probe(command: tuple[str, ...], program: str, what: str) -> Compiler:
    resolved = os.path.realpath(program)
    try:
        mtime = os.stat(resolved).st_mtime_ns
    except OSError:
        mtime = 0
    return _probe_once(command, program, resolved, mtime, what)


@cache
def _probe_once(command: tuple[str, ...], program: str, resolved: str, mtime_ns: int, what: str) -> Compiler:
    """``--version`` once per program and modification time (an upgrade is probed again)."""
    argv = (program, *command[1:])
    try:
        r = subprocess.run([*argv, "--version"], capture_output=True, text=True, timeout=VERSION_TIMEOUT_S)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise CompilerMissing(f"{what}: {program} does not run ({exc}); {INSTALL_HINT}") from None
    text = r.stdout.strip()
    if r.returncode != 0 or not text:
        raise CompilerMissing(f"{what}: '{program} --version' failed; {INSTALL_HINT}")
    return Compiler(command=command, path=program, argv=argv, family=family_of(text),
                    version=version_of(text), identity=f"{resolved}\n{text}")


_WIDTH_WORDS = ((re.compile(r"\b(?:int|unsigned|short)\b"), "int is 32 bits here, 16 on the board"),
                (re.compile(r"(?<!long\s)\blong\b(?!\s+(?:long|double)\b)"), "long 64 bits, 32 there"),
                (re.compile(r"(?<!long\s)\bdouble\b"), "double 64 bits, 32 there"))


def native_widths_note(lab_text: str) -> str:
    """What a native build of a lab is told before its run: where the host's compiler makes it
    differ from the board (and from crslab's WebAssembly build, which has the board's widths and
    layout): ``int``, ``long`` and ``double`` are wider on a 64-bit host, for those the lab uses (no
    flag of gcc or clang gives an x86-64 shared object a 16-bit ``int`` or a 32-bit ``double``), and
    its globals lie where the host's compiler puts them, not where the TI linker does.

    >>> native_widths_note("long long n; long double x;")[:64]
    'built natively: its globals lie where the host compiler puts the'
    >>> native_widths_note("int mode; long mycount = 0; /* double */")[:80]
    'built natively: int is 32 bits here, 16 on the board, long 64 bits, 32 there, an'
    """
    from crslab.lab.variables import _without_preprocessor, strip_comments

    code = _without_preprocessor(strip_comments(lab_text, literals=True))
    widths = [said for pattern, said in _WIDTH_WORDS if pattern.search(code)]
    return ("built natively: " + (", ".join(widths) + ", and " if widths else "")
            + "its globals lie where the host compiler puts them, not where the TI linker does (a store past "
              "an array's end meets another neighbour); crslab sim without --native runs the board's widths "
              "and layout")
