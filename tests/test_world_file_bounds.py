"""Every number a world file holds has its range, and a hostile world file is one line (issue 38:
a 400-digit integer or deep nesting gave a traceback, ``mass_kg = 1e300`` ran on with NaN): each
key of the contest world set just past its range is refused at its own line, naming the key and the
range; a file too large, too deep or holding a number beyond any use is refused by ``crslab sim``
with one line and exit status 2 before anything runs."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from crslab.world import WorldError, load_world, world_file
from crslab.world.world_file import _FIELDS

CONTEST_TEXT = world_file("contest")[0].read_text()
LINES = CONTEST_TEXT.splitlines()


def line_of(table: str, key: str) -> int:
    """The 1-based line that sets ``key`` in ``[table]`` of the contest world (found by scanning
    the text, not by the reader under test)."""
    start = LINES.index(f"[{table}]")
    for i in range(start + 1, len(LINES)):
        if LINES[i].startswith("["):
            break
        if re.match(rf"{re.escape(key)}\s*=", LINES[i]):
            return i + 1
    raise AssertionError(f"{table}.{key} is not set in the contest world")


def numeric_keys() -> list[tuple[str, str]]:
    return [(table, key) for table, (_, kinds) in _FIELDS.items() for key, kind in kinds.items()
            if not kind.boolean]


def test_the_contest_world_sets_every_key_a_world_may_hold():
    for table, key in numeric_keys():
        line_of(table, key)


@pytest.mark.parametrize("table, key", numeric_keys(), ids=[".".join(k) for k in numeric_keys()])
def test_every_number_past_its_range_is_refused_at_its_line(tmp_path, table, key):
    kind = _FIELDS[table][1][key]
    assert kind.maximum is not None, f"{table}.{key} has no maximum"
    assert kind.minimum is not None or kind.positive, f"{table}.{key} has no minimum"
    n = line_of(table, key)
    for bad, says in [(kind.maximum * 1.5 + 1.0, f"must be at most {kind.maximum:g}"),
                      (-1.0 if kind.positive else kind.minimum - 1.0,
                       "must be > 0" if kind.positive else f"must be at least {kind.minimum:g}")]:
        lines = list(LINES)
        if kind.points:  # the first point's x (the list goes on over the next lines)
            lines[n - 1] = re.sub(r"\[\[[^,]+,", f"[[{bad!r},", lines[n - 1], count=1)
        elif kind.count:
            lines[n - 1] = f"{key} = [" + ", ".join([repr(bad)] * kind.count) + "]"
        else:
            lines[n - 1] = f"{key} = {bad!r}"
        path = tmp_path / "bench.toml"
        path.write_text("\n".join(lines) + "\n")
        with pytest.raises(WorldError) as e:
            load_world(path)
        assert str(e.value).startswith(f"{path}:{n}: {table}.{key}: {says}, got "), str(e.value)


def test_a_contest_that_asks_for_a_peg_deeper_than_the_hole_is_refused(tmp_path):
    depth = line_of("hole", "depth_m")
    assert LINES[depth - 1].split("#")[0].split() == ["depth_m", "=", "0.062"]
    n = line_of("contest", "peg_min_depth_m")
    for asked, ok in [("0.0619", True), ("0.062", False)]:
        lines = list(LINES)
        lines[n - 1] = f"peg_min_depth_m = {asked}"
        path = tmp_path / "bench.toml"
        path.write_text("\n".join(lines) + "\n")
        if ok:
            assert load_world(path).contest.peg_min_depth_m == float(asked)
            continue
        says = f"{path}:{n}: contest.peg_min_depth_m: 0.062 m is not shallower than the hole (0.062 m deep)"
        with pytest.raises(WorldError, match=re.escape(says)):
            load_world(path)


MASS = line_of("peg", "mass_kg")


@pytest.mark.parametrize("text, says", [
    (CONTEST_TEXT.replace("mass_kg = 0.030 ", "mass_kg = " + "9" * 400 + " ", 1),
     f"{{path}}:{MASS}: peg.mass_kg: a whole number of 400 digits is too large"),
    (CONTEST_TEXT.replace("mass_kg = 0.030 ", "mass_kg = 1e300 ", 1),
     f"{{path}}:{MASS}: peg.mass_kg: 1e300 is too large a number"),
    (CONTEST_TEXT.replace("mass_kg = 0.030 ", "mass_kg = 1e-300 ", 1),
     f"{{path}}:{MASS}: peg.mass_kg: 1e-300 is too small a number"),
    (CONTEST_TEXT + "[extra]\nx = " + "[" * 5000 + "\n",
     f"{{path}}:{len(LINES) + 2}: extra.x: nested too deep"),
    (CONTEST_TEXT + "#" * 2_000_000 + "\n", "{path}: is larger than a world file may be"),
], ids=["400 digits", "1e300", "1e-300", "deep nesting", "2 MB"])
def test_a_hostile_world_file_is_one_line_and_nothing_runs(tmp_path, text, says):
    path = tmp_path / "bench.toml"
    path.write_text(text)
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--duration", "0.2",
                        "--no-c28x-check", "--world", str(path)], capture_output=True, text=True,
                       timeout=120, env=os.environ)
    assert r.returncode == 2, r.stderr
    assert r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("crslab sim: " + says.format(path=path)), r.stderr
