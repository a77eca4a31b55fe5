"""zig's first link for wasm32 builds its C library (1 to 2 minutes of CPU). crslab does it once per
installation (``make venv``, ``crslab doctor``: ``python -m crslab.lab.prepare``), says so on stderr while
it lasts, and keeps it beside crslab; a first build on a fresh cache (crslab's and zig's) then links
the kept library and zig builds nothing. This test prepares one afresh in a folder of its own
(``CRSLAB_ZIG_LIBC_DIR``); the rest of the suite uses the installation's."""

import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def env_of(tmp_path: Path, caches: str) -> dict:
    return {**os.environ, "CRSLAB_ZIG_LIBC_DIR": str(tmp_path / "libc"),
            "ZIG_GLOBAL_CACHE_DIR": str(tmp_path / caches / "zig"),
            "CRSLAB_CACHE_DIR": str(tmp_path / caches / "c")}


def sim(env: dict) -> subprocess.CompletedProcess:
    lab = ROOT / "tests" / "labs" / "persistent_tau.c"
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--fast", "--quiet",
                           "--no-c28x-check", "--duration", "0.01"], capture_output=True, text=True, env=env,
                          timeout=900)


def test_zig_s_c_library_is_built_once_with_its_progress_and_a_fresh_cache_builds_it_no_more(tmp_path):
    prepare = subprocess.run([sys.executable, "-m", "crslab.lab.prepare"], capture_output=True, text=True,
                             env=env_of(tmp_path, "install"), timeout=2000)
    assert prepare.returncode == 0, prepare.stderr
    lines = prepare.stderr.splitlines()
    assert lines[0] == ("crslab: preparing the WebAssembly compiler (zig's C library for wasm32-wasi; once "
                        "per installation, 1 to 2 minutes)")
    assert all(re.fullmatch(r"crslab:   still building zig's C library: \d+ s", line) for line in lines[1:-1])
    assert re.fullmatch(r"crslab: the WebAssembly compiler is ready \(\d+ s, kept in .*\)", lines[-1]), lines
    kept = list((tmp_path / "libc").iterdir())
    assert len(kept) == 1 and (kept[0] / "manifest.json").is_file()
    assert any(p.name.endswith("libc.a") for p in kept[0].iterdir())

    # a student's first run on a fresh cache: zig's own cache gets no C library
    first = sim(env_of(tmp_path, "fresh"))
    assert first.returncode == 0, first.stderr
    assert "WebAssembly compiler" not in first.stderr
    assert not list((tmp_path / "fresh" / "zig").rglob("libc.a"))
    assert not list((tmp_path / "fresh" / "zig").rglob("libcompiler_rt.a"))


def test_the_page_shows_each_line_of_the_wait_as_its_status():
    """crslab serve's first build before zig's C library is kept: what prepare() says on stderr goes
    to the page line by line as ``building`` messages (app.js shows each as the status)."""
    import json

    from crslab.serve.page_process import PageProgress

    sent: list[bytes] = []
    page = PageProgress(sent.append)
    page.write("crslab: preparing the WebAssembly compiler (zig's C library for wasm32-wasi; once per ")
    assert sent == []  # a line is sent when it is whole
    page.write("installation, 1 to 2 minutes)\ncrslab:   still building zig's C library: 10 s\n")
    assert [json.loads(m) for m in sent] == [
        {"type": "building", "message": "preparing the WebAssembly compiler (zig's C library for "
                                        "wasm32-wasi; once per installation, 1 to 2 minutes)…"},
        {"type": "building", "message": "still building zig's C library: 10 s…"}]
    assert not page.isatty()
