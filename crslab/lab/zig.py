"""zig, the C compiler crslab builds WebAssembly firmware with (``zig cc``: clang with a C library for
wasm32), from the ``ziglang`` package on PyPI, so no system compiler is needed.

Its first use for a target builds that target's C library into zig's cache, which takes about
20 s; :func:`prepare` does it with a note and a running clock on stderr (never silently), and
remembers that it is done. zig's cache lives in crslab's (``<cache>/zig``), so clearing one clears
both.

>>> zig_cc()[-1]
'cc'
>>> zig_cc()[0].endswith("zig")
True
"""

from __future__ import annotations

import importlib.util
import os
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import TextIO

from crslab.cache import cache_dir

FIRST_USE_TIMEOUT_S = 600.0
"""How long zig's first build of a C library may take (about 20 s on a laptop)."""
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


def zig_version() -> str:
    """zig's version, as the ``ziglang`` package records it."""
    from importlib.metadata import version

    return version("ziglang")


ZIG_CACHE_ENV = "ZIG_GLOBAL_CACHE_DIR"
"""zig's own setting for its global cache; crslab uses it when it is set."""


def zig_cache() -> Path:
    """zig's global cache (the C libraries it builds once per target): ``$ZIG_GLOBAL_CACHE_DIR``
    when set, else ``zig/`` in crslab's build cache.

    >>> import os, tempfile
    >>> os.environ[ZIG_CACHE_ENV] = tempfile.mkdtemp()
    >>> zig_cache() == Path(os.environ.pop(ZIG_CACHE_ENV))
    True
    """
    own = os.environ.get(ZIG_CACHE_ENV)
    return Path(own) if own else cache_dir() / "zig"


def zig_environment(local_cache: Path | None = None) -> dict[str, str]:
    """The environment zig runs in: its global cache in crslab's, and the build's own local cache."""
    env = dict(os.environ)
    env[ZIG_CACHE_ENV] = str(zig_cache())
    if local_cache is not None:
        env["ZIG_LOCAL_CACHE_DIR"] = str(local_cache)
    return env


def _stamp(target: str) -> Path:
    return zig_cache() / f"crslab-ready-{target}-{zig_version()}"


def is_prepared(target: str) -> bool:
    """Whether zig's C library for ``target`` is already built (a compile then takes ~60 ms)."""
    return _stamp(target).exists()


PROBE = ("#include <math.h>\n#include <stdio.h>\n"
         "int crs_probe(double x) { char b[32]; return snprintf(b, 32, \"%f\", sin(x)); }\n")


def prepare(target: str, flags: list[str], stream: TextIO | None = None) -> None:
    """Build zig's C library for ``target`` once (a tiny program compiled and linked with
    ``flags``), saying so on ``stream`` (default stderr) with the seconds it has taken so far.
    Raises ``RuntimeError`` with zig's message when zig cannot build it."""
    if is_prepared(target):
        return
    stream = stream if stream is not None else sys.stderr
    zig_cache().mkdir(parents=True, exist_ok=True)
    stream.write(f"crslab: preparing the WebAssembly compiler (zig's C library for {target}; first use "
                 "only, about 20 s)\n")
    stream.flush()
    done = threading.Event()
    start = time.monotonic()

    def tick() -> None:  # a running clock on a terminal, nothing on a pipe
        while not done.wait(1.0):
            stream.write(f"\r  {time.monotonic() - start:4.0f} s")
            stream.flush()

    clock = threading.Thread(target=tick, daemon=True) if stream.isatty() else None
    if clock is not None:
        clock.start()
    try:
        with tempfile.TemporaryDirectory(prefix="crslab-zig-") as tmp:
            src = Path(tmp) / "probe.c"
            src.write_text(PROBE)
            from crslab.lab.compile_process import run_compile

            r = run_compile([*zig_cc(), f"--target={target}", *flags, str(src), "-o",
                             str(Path(tmp) / "probe")],
                            cwd=Path(tmp), env=zig_environment(Path(tmp) / "cache"),
                            timeout_s=FIRST_USE_TIMEOUT_S, cpu_s=int(FIRST_USE_TIMEOUT_S),
                            memory_bytes=PREPARE_MEMORY_BYTES)
    finally:
        done.set()
        if clock is not None:
            clock.join()
            stream.write("\r")
    if r.timed_out:
        raise RuntimeError(f"zig did not finish building its C library for {target} within "
                           f"{FIRST_USE_TIMEOUT_S:.0f} s")
    if r.returncode != 0:
        first = next((line for line in r.stderr.splitlines() if line.strip()), "no message")
        raise RuntimeError(f"zig cannot build its C library for {target}: {first}")
    _stamp(target).touch()
    stream.write(f"crslab: the WebAssembly compiler is ready ({time.monotonic() - start:.0f} s)\n")
    stream.flush()
