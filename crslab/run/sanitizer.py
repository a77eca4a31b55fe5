"""Sanitized runs (``--sanitize``): the AddressSanitizer runtime to preload into the worker, and
the first finding of a sanitizer report as one phrase naming the user's file and line."""

from __future__ import annotations

import re
from pathlib import Path

from crslab.lab.compiler import Compiler, find_compiler


def asan_runtime(compiler: Compiler | None = None) -> str:
    """Path of the AddressSanitizer runtime of the compiler that built the lab (default: the one
    labs are built with now), to preload into the sanitized worker."""
    return (compiler or find_compiler()).asan_runtime()


_ASAN = re.compile(r"ERROR: AddressSanitizer: ([\w-]+)")
_ASAN_ACCESS = re.compile(r"^(READ|WRITE) of size (\d+)", re.MULTILINE)
_FRAME = re.compile(r"#\d+ 0x[0-9a-f]+ in (\w+) (\S+?):(\d+)")
_UBSAN = re.compile(r"^(\S+?):(\d+):\d+: runtime error: (.+)$", re.MULTILINE)


def summarize_sanitizer_report(text: str, lab_file: str) -> str | None:
    """One phrase for the first AddressSanitizer or UBSan finding in ``lab_file``.

    >>> summarize_sanitizer_report(
    ...     "==1==ERROR: AddressSanitizer: global-buffer-overflow on address 0x1\\n"
    ...     "WRITE of size 4 at 0x1 thread T0\\n    #0 0x7f in lab /x/mylab.c:31\\n", "mylab.c")
    'AddressSanitizer: global-buffer-overflow (WRITE of size 4) at mylab.c:31 in lab()'
    """
    m = _ASAN.search(text)
    if m:
        access = _ASAN_ACCESS.search(text)
        what = f" ({access.group(1)} of size {access.group(2)})" if access else ""
        frames = _FRAME.findall(text)
        mine = [f for f in frames if Path(f[1]).name == lab_file] or frames
        where = f" at {Path(mine[0][1]).name}:{mine[0][2]} in {mine[0][0]}()" if mine else ""
        return f"AddressSanitizer: {m.group(1)}{what}{where}"
    u = _UBSAN.search(text)
    if u:
        return f"UBSan: {u.group(3)} at {Path(u.group(1)).name}:{u.group(2)}"
    return None
