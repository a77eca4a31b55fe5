"""Issue 30's acceptance: crslab's own final-project lab (``crslab new final``) completes all four
tasks of the contest world, and each variant that breaks one task fails that task, named with
its evidence: stiff in x-y at the hole with the hole 1 cm off, the groove followed above its
plate's top (the starter, compliant across, follows a groove 4 mm from its waypoints), a press
target deep enough to break the egg, a path through the obstacle. ``crslab grade --contest`` on a
small class gives a column per task and a JUnit case per task. Each lab runs once
(module-scoped), as a user runs it: ``crslab contest --json`` in a process of its own."""

import csv
import json
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from crslab.starters import starter_text
from crslab.world import load_world, world_file

LABS = Path(__file__).parent / "labs"


def crslab(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=600, cwd=cwd)


def variant(text, *swaps):
    """The starter with each (old, new) swapped once; each old must be in it (the test breaks loudly
    when the starter changes under it)."""
    for old, new in swaps:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    return text


STARTER = starter_text("final", "B")
HOLE_ROWS = ("0.10, HOLE, 0.0, 0.8},", "0.20, HOLE, 0.0, 0.0},")


def world_with_hole_moved(folder, dx_m):
    """contest.toml with the hole block moved ``dx_m`` along x: a bench whose hole is not where the
    lab's waypoints think."""
    text = world_file("contest")[0].read_text()
    hole = load_world("contest").hole
    x, y = hole.center_xy_m
    old = None
    for line in text.splitlines():
        if line.replace(" ", "").startswith("center_xy_m=") and str(x) in line:
            old = line
            break
    assert old is not None, "the hole's center_xy_m line of contest.toml"
    path = folder / "contest_hole_off.toml"
    path.write_text(text.replace(old, old.replace(str(x), repr(round(x + dx_m, 6))), 1))
    moved = load_world(path)
    assert moved.hole.center_xy_m[0] == pytest.approx(x + dx_m) and moved.egg == load_world("contest").egg
    return path


def world_with_groove_moved(folder, dy_m):
    """contest.toml with the groove's Z moved ``dy_m`` along y: a bench whose groove is a few mm
    from the lab's waypoints (benches differ by about that much)."""
    text = world_file("contest")[0].read_text()
    corners = load_world("contest").groove.corners_xy_m
    for x, y in corners:
        old = f"[{x!r}, {y!r}]"
        assert text.count(old) == 1, old
        text = text.replace(old, f"[{x!r}, {round(y + dy_m, 6)!r}]")
    path = folder / "contest_groove_off.toml"
    path.write_text(text)
    moved = load_world(path)
    assert [c[1] for c in moved.groove.corners_xy_m] == pytest.approx([c[1] + dy_m for c in corners])
    return path


VARIANTS = {
    "starter": (STARTER, None),
    # the peg stiff in x and y over a hole 1 cm from where the waypoints put it: it cannot slide in
    "hole_stiff": (variant(STARTER, *((r, r.replace("HOLE", "XYZSTIFF")) for r in HOLE_ROWS)), "hole_off"),
    # the groove's height taught 1 cm above the plate's top: the peg slides along the top, never in
    "groove_high": (variant(STARTER, ("#define GROOVE_Z 0.213", "#define GROOVE_Z 0.235")), None),
    # the starter itself on that groove: compliant across, the walls guide it
    "starter_groove_off": (STARTER, "groove_off"),
    # a press past the egg's breaking force (20 N): 4 units, about 24 N, once the friction gives way
    "egg_deep": (variant(STARTER, ("float Fpress = 1.2;", "float Fpress = 4.0;")), None),
    # from the hole to the groove 4 cm below the obstacle's top (0.30 m): through it
    "through_obstacle": (variant(STARTER, ("{0.200, 0.110, 0.380,", "{0.200, 0.110, 0.260,"),
                                 ("{HOLE_X, HOLE_Y, 0.380,", "{HOLE_X, HOLE_Y, 0.260,")), None),
}


@pytest.fixture(scope="module")
def cards(tmp_path_factory):
    folder = tmp_path_factory.mktemp("contest")
    worlds = {"hole_off": world_with_hole_moved(folder, 0.01),
              "groove_off": world_with_groove_moved(folder, 0.004)}
    out = {}
    for name, (text, world) in VARIANTS.items():
        lab = folder / f"{name}.c"
        lab.write_text(text)
        args = ["contest", "--lab", lab, "--json"] + (["--world", worlds[world]] if world else [])
        r = crslab(*args)
        assert r.returncode in (0, 1), r.stderr
        out[name] = json.loads(r.stdout), r.returncode
    return out


def test_the_starter_completes_all_four_tasks(cards):
    card, status = cards["starter"]
    tasks = card["tasks"]
    assert status == 0 and all(t["done"] for t in tasks.values()), card
    contest = load_world("contest").contest
    assert tasks["peg"]["depth_m"] >= contest.peg_min_depth_m and tasks["peg"]["held_s"] >= contest.peg_hold_s
    assert not tasks["obstacle"]["touched"] and tasks["groove"]["left_at"] is None
    lo, hi = contest.band_g
    assert lo <= tasks["egg"]["peak_g"] <= hi and not tasks["egg"]["broken"]
    assert tasks["egg"]["in_band_s"] >= contest.hold_s
    assert card["time_s"] is not None and 0 < card["time_s"] < 30


def test_the_starter_follows_a_groove_4_mm_from_its_waypoints(cards):
    card, status = cards["starter_groove_off"]
    groove = card["tasks"]["groove"]
    assert status == 0 and groove["done"] and groove["left_at"] is None, card
    assert groove["share"] >= load_world("contest").contest.groove_min_share



@pytest.mark.parametrize("name, task", [
    ("hole_stiff", "peg"),
    ("groove_high", "groove"),
    ("egg_deep", "egg"), ("through_obstacle", "obstacle")])
def test_each_variant_fails_the_task_it_breaks(cards, name, task):
    card, status = cards[name]
    assert status == 1 and not card["tasks"][task]["done"] and card["time_s"] is None, card
    evidence = card["tasks"][task]
    if task == "peg":
        assert evidence["held_s"] < load_world("contest").contest.peg_hold_s
    elif task == "groove":
        assert evidence["share"] == 0.0 and evidence["left_at"] is None  # never in it
    elif task == "egg":
        assert evidence["broken"] and evidence["peak_g"] > 1000 * 20.0 / 9.80665 * 0.99
    else:
        assert evidence["touched"] and evidence["max_force_n"] > 0.05


def test_the_card_s_lines_and_picture(tmp_path):
    lab = tmp_path / "final.c"
    lab.write_text(STARTER)
    r = crslab("contest", "--lab", lab, "-o", tmp_path / "pics" / "card.png")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert [line.split()[:2] for line in lines] == [["peg", "done"], ["obstacle", "done"], ["groove", "done"],
                                                   ["egg", "done"], ["time", lines[4].split()[1]]]
    assert (tmp_path / "pics" / "card.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("args, said", [
    (["--lab", "nowhere.c"], "nowhere.c: no such lab file"),
    (["--lab", LABS / "does_not_compile.c"], "does not compile"),
    (["--lab", "final.c", "--world", "atlantis"], "atlantis"),
])
def test_bad_input_is_one_line(tmp_path, args, said):
    (tmp_path / "final.c").write_text(STARTER)
    r = crslab("contest", *args, cwd=tmp_path)
    assert r.returncode == 2 and r.stdout == "", r.stderr
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("crslab contest: ") and said in last and "Traceback" not in r.stderr, r.stderr


def test_grade_contest_gives_a_column_per_task_and_a_junit_case_per_task(tmp_path):
    subs = tmp_path / "class"
    subs.mkdir()
    (subs / "alice.c").write_text(STARTER)
    (subs / "bob.c").write_text(VARIANTS["egg_deep"][0])
    (subs / "carol.c").write_text((LABS / "does_not_compile.c").read_text())
    r = crslab("grade", subs, "--contest", "-o", tmp_path / "out", "--jobs", "2")
    assert r.returncode == 1, r.stderr
    rows = {row["submission"]: row for row in csv.DictReader(open(tmp_path / "out" / "grades.csv"))}
    assert rows["alice.c"]["result"] == "complete" and rows["alice.c"]["tasks_done"] == "4"
    assert all(rows["alice.c"][f"{t}_done"] == "1" for t in ("peg", "obstacle", "groove", "egg"))
    assert float(rows["alice.c"]["time_s"]) > 0
    # the broken egg lets the push carry the arm down onto the obstacle too
    bob = rows["bob.c"]
    assert bob["result"] == f"{bob['tasks_done']} of 4" and bob["egg_done"] == "0"
    assert rows["bob.c"]["egg_broken"] == "1" and rows["bob.c"]["time_s"] == ""
    assert rows["carol.c"]["result"] == "does not compile" and rows["carol.c"]["peg_done"] == ""
    suite = ET.parse(tmp_path / "out" / "junit.xml").getroot()
    cases = {(c.get("classname"), c.get("name")): c for c in suite.iter("testcase")}
    assert len(cases) == 12
    tasks = ("peg", "obstacle", "groove", "egg")
    assert all(len(list(cases["crslab.contest.alice.c", t])) == 0 for t in tasks)
    assert cases["crslab.contest.bob.c", "egg"].find("failure") is not None
    assert "BROKEN" in cases["crslab.contest.bob.c", "egg"].find("failure").get("message")
    assert cases["crslab.contest.bob.c", "peg"].find("failure") is None
    assert cases["crslab.contest.carol.c", "egg"].find("error") is not None
    board = r.stdout.splitlines()
    assert board[1].split()[:3] == ["1", "alice.c", "complete"] and board[2].split()[:2] == ["2", "bob.c"]
