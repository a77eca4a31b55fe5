"""``crslab grade`` bounds every submission's memory: a leaking lab is classed crashed and the
rest of the class is graded. A WebAssembly firmware has the board's memory and no more; a native
one (--native) is limited by default."""

import csv
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]



@pytest.mark.parametrize("board", ["wasm", "native"])
def test_grade_limits_memory_by_default(tmp_path, board):
    subs = tmp_path / "subs"
    subs.mkdir()
    shutil.copy(ROOT / "tests" / "labs" / "faulty" / "memory_hog.c", subs / "leaky.c")
    shutil.copy(ROOT / "csrc" / "labs" / "lab1_kinematics.c", subs / "good.c")
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "crslab", "grade", str(subs), "--reference",
                        str(ROOT / "csrc" / "labs" / "lab1_kinematics.c"), "--scenario", "hands_off",
                        "--duration", "6", "--out", str(out), *(["--native"] if board == "native" else [])],
                       capture_output=True, text=True, timeout=300)
    rows = {row["submission"]: row for row in csv.DictReader((out / "grades.csv").open())}
    assert rows["good.c"]["result"] == "pass"
    assert rows["leaky.c"]["result"] == "crashed", rows["leaky.c"]["detail"]  # the detail says why if not
    if board == "native":
        assert rows["leaky.c"]["detail"].endswith("its memory limit was 2048 MB")
    else:  # malloc found no room and returned NULL, which memset ran through
        assert rows["leaky.c"]["detail"].startswith("leaky.c read or wrote outside its memory ")
    assert r.returncode == 1  # not every submission passed
