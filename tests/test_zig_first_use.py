"""zig's first use on a machine builds its C library for wasm32 (about 20 s): crslab says so on
stderr before it starts and when it is done, and never again once it is built. This test builds
one afresh in a zig cache of its own (the rest of the suite shares the user's: tests/conftest.py)."""

import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def sim(tmp_path: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "ZIG_GLOBAL_CACHE_DIR": str(tmp_path / "zig"),
           "CRSLAB_CACHE_DIR": str(tmp_path / "c")}
    lab = ROOT / "tests" / "labs" / "persistent_tau.c"
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--lab", str(lab), "--fast", "--quiet",
                           "--no-c28x-check", "--duration", "0.01"], capture_output=True, text=True, env=env,
                          timeout=900)


def test_the_first_use_of_zig_says_what_it_builds_and_when_it_is_ready(tmp_path):
    first = sim(tmp_path)
    assert first.returncode == 0, first.stderr
    lines = first.stderr.splitlines()
    assert lines[0] == ("crslab: preparing the WebAssembly compiler (zig's C library for wasm32-wasi; first "
                        "use only, about 20 s)")
    assert re.fullmatch(r"crslab: the WebAssembly compiler is ready \(\d+ s\)", lines[1]), lines
    assert (tmp_path / "zig").is_dir() and any((tmp_path / "zig").iterdir())
    again = sim(tmp_path)
    assert again.returncode == 0 and "WebAssembly compiler" not in again.stderr
