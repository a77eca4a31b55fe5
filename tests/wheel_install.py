"""The wheel as a student installs it, shared by the packaging test and the docs test.

From a clean copy of this checkout (its tracked files, nothing built), ``python -m build`` makes
the sdist and then the wheel *from the sdist*, so the sdist is shown to hold what the wheel build
needs. Then docs/first-lab.md's install block runs as written in a fresh work folder holding the
wheel: it makes ``.venv`` there, installs the wheel and pytest into it (from PyPI, or pip's
cache) and runs ``crslab doctor``. Every command then runs from that folder, outside the
checkout, with a fresh build cache, so each lab is compiled from the files the wheel installed.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def run(*cmd, cwd=None, env=None, timeout=600, stdin=None):
    return subprocess.run([str(c) for c in cmd], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout, input=stdin)


def code_blocks(markdown: Path, language: str) -> list[str]:
    """The fenced blocks of ``language`` in ``markdown``, in order, as written."""
    return re.findall(rf"^```{language}\n(.*?)^```", markdown.read_text(), flags=re.MULTILINE | re.DOTALL)


def clean_copy(dest: Path) -> Path:
    """The checkout's tracked files as they are now (uncommitted edits included), without anything
    built or cached in it."""
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    for rel in filter(None, files.decode().split("\0")):
        src = ROOT / rel
        if src.is_file():
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / rel)
    return dest


@dataclass
class Installed:
    """A work folder whose ``.venv`` holds the wheel, made by first-lab.md's install block."""

    venv: Path
    work: Path
    env: dict
    wheel: Path
    sdist: Path
    install_output: str

    def crslab(self, *args, cwd=None, timeout=300):
        return run(self.venv / "bin" / "crslab", *args, cwd=cwd or self.work, env=self.env, timeout=timeout)

    def shell(self, script: str, cwd=None, timeout=600):
        """``script`` (a docs block, as written) in bash with the venv active, stopping at the
        first failing command."""
        return run("bash", "-c", "set -euo pipefail\n. .venv/bin/activate\ncd \"$CRSLAB_DOC_CWD\"\n" + script,
                   cwd=self.work, env={**self.env, "CRSLAB_DOC_CWD": str(cwd or self.work)}, timeout=timeout)


NO_BYTECODE = {"PIP_COMPILE": "0"}
"""pip's own setting for ``--compile``, off (pip reads PIP_NO_COMPILE=1 as compile *on*): no
byte-compiling of what it installs. The wheel's dependencies are 1.5 GB of about 7,600 modules
(ziglang, rerun-sdk, pyarrow, scipy, ...), which pip would compile to .pyc at install for half a
minute of CPU; a run imports a few hundred of them, compiled when first imported. What is
installed, and how a student's commands run it, is the same."""


def kept_zig_libc(dest: Path) -> dict[str, str]:
    """zig's C library as this checkout's installation prepared it, copied to ``dest``, as
    ``CRSLAB_ZIG_LIBC_DIR`` for the wheel's environment: its ``crslab doctor`` then finds the
    library prepared, as a second installation of the same zig would need it built, and does not
    spend one to two minutes of both cores building it again. Building it from nothing, with its
    progress lines, is tests/test_zig_first_use.py's. Nothing when this installation has none (no
    zig): the wheel's doctor then builds its own."""
    from crslab.lab.zig import LIBC_ENV, libc_homes

    for home in libc_homes():
        if any(home.glob("*/manifest.json")):
            shutil.copytree(home, dest)
            return {LIBC_ENV: str(dest)}
    return {}


def install_wheel(base: Path) -> Installed:
    """Build the wheel from a clean copy of the checkout and install it as first-lab.md says."""
    source = clean_copy(base / "crslab-src")
    dist = base / "dist"
    # the sdist, then the wheel from it (each in an isolated environment of its own, which pip fills)
    r = run(sys.executable, "-m", "build", "--outdir", dist, source, env={**os.environ, **NO_BYTECODE})
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    [wheel], [sdist] = sorted(dist.glob("*.whl")), sorted(dist.glob("*.tar.gz"))
    work = base / "work"
    work.mkdir()
    shutil.copy(wheel, work / wheel.name)  # "the wheel your course hands out", in the student's folder
    tools = base / "bin"  # `python3` is the Python running these tests (not another one on PATH)
    tools.mkdir()
    (tools / "python3").symlink_to(sys.executable)
    # a student's shell: no PYTHONDONTWRITEBYTECODE either (a module is compiled when first imported
    # and kept, as on any machine: see NO_BYTECODE)
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "VIRTUAL_ENV", "CRSLAB_CACHE_DIR", "PYTHONDONTWRITEBYTECODE")}
    env.update(PATH=f"{tools}{os.pathsep}{os.environ['PATH']}", CRSLAB_CACHE_DIR=str(base / "cache"),
               PYTHONNOUSERSITE="1", **NO_BYTECODE, **kept_zig_libc(base / "zig-libc"))
    [install, *_] = code_blocks(DOCS / "first-lab.md", "sh")
    assert install.startswith("python3 -m venv .venv"), install
    r = run("bash", "-c", "set -euo pipefail\n" + install, cwd=work, env=env)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    venv = work / ".venv"
    env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env['PATH']}"
    return Installed(venv, work, env, wheel, sdist, r.stdout)
