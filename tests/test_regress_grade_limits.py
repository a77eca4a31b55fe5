"""``crslab grade`` bounds every submission's memory by default: a leaking lab is classed
crashed and the rest of the class is graded."""

import csv
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_grade_limits_memory_by_default(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    shutil.copy(ROOT / "tests" / "labs" / "faulty" / "memory_hog.c", subs / "leaky.c")
    shutil.copy(ROOT / "csrc" / "labs" / "lab1_kinematics.c", subs / "good.c")
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "crslab", "grade", str(subs), "--reference",
                        str(ROOT / "csrc" / "labs" / "lab1_kinematics.c"), "--scenario", "hands_off",
                        "--duration", "6", "--out", str(out)], capture_output=True, text=True, timeout=300)
    rows = {row["submission"]: row for row in csv.DictReader((out / "grades.csv").open())}
    assert rows["good.c"]["result"] == "pass"
    assert rows["leaky.c"]["result"] == "crashed"
    assert rows["leaky.c"]["detail"].endswith("its memory limit was 2048 MB")
    assert r.returncode == 1  # not every submission passed
