"""``crslab contest`` and ``crslab grade --contest`` as a user runs them (issues 30 and 37):
crslab's own final-project lab (``crslab new final``) completes all four tasks of the contest
world, and each variant that breaks one task fails that task, named with its evidence: stiff in
x-y at the hole with the hole 1 cm off (where the peg stopped), the groove followed above its
plate's top (how high it stayed; the starter, compliant across, follows a groove 4 mm from its
waypoints), a press that breaks the egg (what broke it, the peak before), a path through the
obstacle (what touched it); the motor board's cut and a lab() call over the budget on the card. A
lab that crashes gets its card up to the crash. ``crslab grade --contest`` grades a class of files
and student folders: ranks (equal times equal), a detail for every result, each card, picture
and transcript. Each lab runs once (module-scoped), in a process of its own: ``crslab contest
--json``."""

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


ABOVE_THE_PLATE_Z = load_world("contest").groove.top_z_m + 0.010


VARIANTS = {
    "starter": (STARTER, None),
    # the peg stiff in x and y over a hole 1 cm from where the waypoints put it: it cannot slide in
    "hole_stiff": (variant(STARTER, *((r, r.replace("HOLE", "XYZSTIFF")) for r in HOLE_ROWS)), "hole_off"),
    # the starter itself on that groove: compliant across, the walls guide it
    "starter_groove_off": (STARTER, "groove_off"),
    # a press past the egg's breaking force (25 N): 8 units, about 48 N, 31 N on the egg once the
    # joints' static friction (about 17 N at the tip, models/crs_arm/README.md) gives way
    "egg_deep": (variant(STARTER, ("float Fpress = 1.2;", "float Fpress = 8.0;")), None),
    # from the hole to the groove 4 cm below the obstacle's top (0.30 m): through it
    "through_obstacle": (variant(STARTER, ("{0.200, 0.110, 0.380,", "{0.200, 0.110, 0.260,"),
                                 ("{HOLE_X, HOLE_Y, 0.380,", "{HOLE_X, HOLE_Y, 0.260,")), None),
    # the groove's height taught 1 cm above the plate's top: the peg slides along the top, never in
    "groove_high": (variant(STARTER, ("#define GROOVE_Z 0.213", f"#define GROOVE_Z {ABOVE_THE_PLATE_Z:.4f}")),
                    None),
    # joint 1 commanded 5 units (over the motor board's 4) from lab()'s call 3000 to 4000, and one
    # call (2000, t = 6.1 s) that counts to 100,000: over the budget of 75,000 instructions
    "cut_and_costly": (variant(
        STARTER,
        ("    *tau1 = saturate(*tau1);",
         "    *tau1 = (mycount >= 3000 && mycount < 4000) ? 5.0f : saturate(*tau1);"),
        ("    mycount++;\n}", "    if (mycount == 2000) {\n        long k;\n"
         "        for (k = 0; k < 100000; k++) busy += 1.0f;\n    }\n    mycount++;\n}"),
        ("long mycount = 0;", "long mycount = 0;\nvolatile float busy = 0;")), None),
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


RULES = {"peg_min_depth_m": 0.005, "peg_hold_s": 0.5, "band_g": (500.0, 1000.0), "hold_s": 2.0,
         "hold_tolerance_s": 0.2, "groove_min_share": 0.9}
"""The contest's rules (the world's [contest] defaults, csrc/plant/world_facts.h)."""


def test_the_starter_completes_all_four_tasks(cards):
    card, status = cards["starter"]
    tasks = card["tasks"]
    assert status == 0 and card["complete"] and all(t["done"] for t in tasks.values()), card
    assert tasks["peg"]["depth_m"] >= RULES["peg_min_depth_m"]
    assert tasks["peg"]["held_s"] >= RULES["peg_hold_s"]
    assert not tasks["obstacle"]["touched"] and tasks["obstacle"]["passed"] == "over"
    assert tasks["groove"]["left_at"] is None
    lo, hi = RULES["band_g"]
    assert lo <= tasks["egg"]["peak_g"] <= hi and not tasks["egg"]["broken"]
    assert tasks["egg"]["in_band_s"] >= RULES["hold_s"] - RULES["hold_tolerance_s"]
    assert card["time_s"] is not None and 0 < card["time_s"] < 30
    # as a TA runs it: resting where the lab's offsets say, ended once the arm came to rest
    assert card["rest"] == {"motor_rad": [0.0, -0.42, 0.24], "source": "lab"}
    assert card["run"]["status"] == "ok" and card["run"]["still_since_s"] < card["run"]["end_s"] < 60


def test_the_starter_follows_a_groove_4_mm_from_its_waypoints(cards):
    card, status = cards["starter_groove_off"]
    groove = card["tasks"]["groove"]
    assert status == 0 and groove["done"] and groove["left_at"] is None, card
    assert groove["share"] >= RULES["groove_min_share"]


@pytest.mark.parametrize("name, task", [
    ("hole_stiff", "peg"),
    ("groove_high", "groove"),
    ("egg_deep", "egg"), ("through_obstacle", "obstacle")])
def test_each_variant_fails_the_task_it_breaks(cards, name, task):
    card, status = cards[name]
    assert status == 1 and not card["complete"] and card["time_s"] is None, card
    assert not card["tasks"][task]["done"], card
    evidence = card["tasks"][task]
    if task == "peg":
        # on the block beside the hole (1 cm off): where it stopped, said
        assert evidence["held_s"] < RULES["peg_hold_s"] - RULES["hold_tolerance_s"]
        assert evidence["stopped_at"] is not None
        assert 0.003 < evidence["off_axis_m"] < 0.03
    elif task == "groove":
        # never below the plate's top: how high it stayed, the 1 cm it was told less what the tip
        # sags under gravity on its stiffness
        assert evidence["share"] == 0 and evidence["left_at"] is None
        assert 0.001 < evidence["lowest_above_top_m"] < 0.010
    elif task == "egg":
        assert evidence["broken"] and evidence["broken_by"] == "the press"
        assert evidence["peak_g"] > 1000 * 20.0 / 9.80665 * 0.99
        assert evidence["peak_before_break_g"] < evidence["peak_g"]
    else:
        assert evidence["touched"] and evidence["touched_by"] and evidence["max_force_n"] > 0.05


def test_the_card_says_when_the_motor_board_cut_the_run_and_a_call_over_the_budget(cards):
    card, _ = cards["cut_and_costly"]
    run = card["run"]
    # over 4 units from call 3000 (t = 7.1 s): cut 0.5 s later
    assert run["motor_board_off_at_s"] == pytest.approx(7.6, abs=0.01)
    assert run["over_budget"] == 1


def test_the_card_s_lines_and_picture(tmp_path):
    lab = tmp_path / "final.c"
    lab.write_text(STARTER)
    r = crslab("contest", "--lab", lab, "-o", tmp_path / "pics" / "card.png")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert [line.split()[:2] for line in lines[:5]] == [["peg", "done"], ["obstacle", "done"],
                                                       ["groove", "done"], ["egg", "done"],
                                                       ["time", lines[4].split()[1]]]
    assert [line.split()[0] for line in lines[5:]] == ["rest", "run"]
    assert (tmp_path / "pics" / "card.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_run_it_says_to_watch_is_the_run_it_scored(tmp_path):
    """``crslab sim`` rests the arm at crslab's pose unless told: the command the contest prints
    rests it where the contest did (this lab's offsets, 0.01 rad from crslab's) and runs as long, so
    the scale reads in it, tick for tick, what the card scored."""
    lab = tmp_path / "final.c"
    lab.write_text(variant(STARTER, ("float offset_Enc2_rad = -0.42;", "float offset_Enc2_rad = -0.41;")))
    r = crslab("contest", "--lab", lab, "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    card = json.loads(r.stdout)
    said = "crslab contest: to watch this run: "
    [watch] = [line[len(said):] for line in r.stderr.splitlines() if line.startswith(said)]
    cmd = watch.split()
    assert cmd[:4] == ["crslab", "sim", "--lab", str(lab)] and "--offsets" in cmd
    rows = tmp_path / "watched.csv"
    r = crslab(*cmd[1:], "--fast", "--quiet", "--no-stdin", "--csv", rows, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    with rows.open() as f:
        table = list(csv.reader(f))
    grams = [float(v) for v in (row[table[0].index("scale_g [g]")] for row in table[1:])]
    assert round(max(grams), 1) == card["tasks"]["egg"]["peak_g"]
    assert float(table[-1][table[0].index("t [s]")]) == pytest.approx(card["run"]["end_s"], abs=0.0011)


@pytest.mark.parametrize("args, said", [
    (["--lab", "nowhere.c"], "nowhere.c: no such lab file"),
    (["--lab", LABS / "does_not_compile.c"], "does not compile"),
    (["--lab", "final.c", "--world", "atlantis"], "atlantis"),
    (["--lab", "final.c", "--world", "none"], "world 'none' has no fixtures"),
])
def test_bad_input_is_one_line(tmp_path, args, said):
    (tmp_path / "final.c").write_text(STARTER)
    r = crslab("contest", *args, cwd=tmp_path)
    assert r.returncode == 2 and r.stdout == "", r.stderr
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("crslab contest: ") and said in last and "Traceback" not in r.stderr, r.stderr


# a student's mistake after the peg's task: a stray pointer written at lab()'s call 8000 (t = 12.1 s)
CRASHING = variant(STARTER, ("long mycount = 0;", "long mycount = 0;\nfloat *stray = 0;"),
                   ("    mycount++;\n}",
                    "    if (mycount == 8000) {\n        *stray = 1.0f;\n    }\n    mycount++;\n}"))


def test_a_crashed_lab_gets_its_card_up_to_the_crash(tmp_path):
    lab = tmp_path / "final.c"
    lab.write_text(CRASHING)
    r = crslab("contest", "--lab", lab, "--json")
    assert r.returncode == 3, r.stderr   # crslab sim's status for a crash, the card printed first
    card = json.loads(r.stdout)
    assert card["run"]["status"] == "crashed" and card["run"]["end_s"] == 12.1
    assert "NULL pointer" in card["run"]["message"] and "final.c:" in card["run"]["message"]
    # what it did before the crash counts: the peg was in the hole by then
    assert card["tasks"]["peg"]["done"] and card["tasks"]["peg"]["done_at_s"] < 12.1
    assert not card["tasks"]["egg"]["done"] and card["time_s"] is None


def test_grade_contest_grades_a_class_as_grade_does(tmp_path):
    subs = tmp_path / "class"
    (subs / "alice").mkdir(parents=True)
    # alice: the starter in a folder of her own, its gains in a header of hers
    (subs / "alice" / "gains.h").write_text("#define MY_KGROOVE 60.0\n")
    alice = variant(STARTER, ("float Kgroove = 60.0;", "float Kgroove = MY_KGROOVE;"),
                    ("long mycount = 0;", '#include "gains.h"\nlong mycount = 0;'))
    (subs / "alice" / "final.c").write_text(alice)
    (subs / "bob.c").write_text(STARTER)           # the same run as alice's: ranked equal
    (subs / "carol.c").write_text((LABS / "does_not_compile.c").read_text())
    (subs / "dave.c").write_text(CRASHING)
    # erin's bench rests elsewhere: her own offsets, kept in a header of hers, are where her arm rests
    (subs / "erin").mkdir()
    (subs / "erin" / "bench.h").write_text("float offset_Enc2_rad = -0.41;\n")
    (subs / "erin" / "final.c").write_text(variant(VARIANTS["egg_deep"][0], ("float offset_Enc2_rad = -0.42;",
                                                                             '#include "bench.h"')))
    # frank's header rests his peg in the groove plate: his run is refused, not run where crslab's arm rests
    (subs / "frank").mkdir()
    (subs / "frank" / "bench.h").write_text("float offset_Enc2_rad = 0.9827;\n"
                                            "float offset_Enc3_rad = 0.8446;\n")
    (subs / "frank" / "final.c").write_text(variant(STARTER, ("float offset_Enc2_rad = -0.42;",
                                                              '#include "bench.h"'),
                                                    ("float offset_Enc3_rad = 0.24;", "")))
    out = tmp_path / "out"
    r = crslab("grade", subs, "--contest", "-o", out, "--jobs", "2")
    assert r.returncode == 1, r.stderr
    rows = {row["submission"]: row for row in csv.DictReader(open(out / "grades.csv"))}
    assert set(rows) == {"alice/final.c", "bob.c", "carol.c", "dave.c", "erin/final.c", "frank/final.c"}
    a, b = rows["alice/final.c"], rows["bob.c"]
    assert a["result"] == b["result"] == "complete" and a["tasks_done"] == "4"
    assert all(a[f"{t}_done"] == "1" for t in ("peg", "obstacle", "groove", "egg"))
    assert float(a["time_s"]) > 0 and a["time_s"] == b["time_s"] and a["rank"] == b["rank"] == "1"
    assert (a["rest_motor2_rad"], a["rest_motor3_rad"], a["rest_from"]) == ("-0.420000", "0.240000", "lab")
    erin = rows["erin/final.c"]
    assert (erin["rest_motor2_rad"], erin["rest_motor3_rad"], erin["rest_from"]) == ("-0.410000", "0.240000",
                                                                                   "lab")
    assert erin["result"] == f"{erin['tasks_done']} of 4" and erin["egg_done"] == "0"
    assert erin["egg_broken_by"] == "the_press" and erin["time_s"] == "" and erin["rank"] == "3"
    assert "BROKEN" in erin["detail"] and "by the press" in erin["detail"]
    frank = rows["frank/final.c"]
    assert (frank["result"], frank["status"], frank["rest_motor2_rad"], frank["rest_from"]) == \
        ("unfit", "unfit", "0.982700", "lab")
    assert "the groove plate" in frank["detail"] and frank["peg_done"] == ""
    assert rows["carol.c"]["result"] == "does not compile" and rows["carol.c"]["peg_done"] == ""
    assert "error:" in rows["carol.c"]["detail"]
    dave = rows["dave.c"]
    assert dave["status"] == "crashed" and dave["peg_done"] == "1" and "NULL pointer" in dave["detail"]
    assert all(row["detail"] for row in rows.values())       # every result says why
    # each submission's card (text, picture) and transcript, named as the reports name it
    for name in rows:
        assert (out / "cards" / f"{name}.txt").read_text().strip(), name
        assert (out / "transcripts" / f"{name}.txt").is_file(), name
        if name not in ("carol.c", "frank/final.c"):     # neither ran
            assert (out / "cards" / f"{name}.png").read_bytes()[:4] == b"\x89PNG", name
    dave_card = (out / "cards" / "dave.c.txt").read_text().splitlines()
    assert dave_card[6].startswith("run       crashed at t = 12.100 s")
    suite = ET.parse(out / "junit.xml").getroot()
    cases = {(c.get("classname"), c.get("name")): c for c in suite.iter("testcase")}
    assert len(cases) == 24
    tasks = ("peg", "obstacle", "groove", "egg")
    assert all(len(list(cases["crslab.contest.alice/final.c", t])) == 0 for t in tasks)
    assert "BROKEN" in cases["crslab.contest.erin/final.c", "egg"].find("failure").get("message")
    assert cases["crslab.contest.carol.c", "egg"].find("error") is not None
    board = r.stdout.splitlines()
    assert [line.split()[:3] for line in board[1:3]] == [["1", "alice/final.c", "complete"],
                                                         ["1", "bob.c", "complete"]]
