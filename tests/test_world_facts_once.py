"""Every world fact has one home, in C (csrc/plant/world.h, world.c, world_facts.h), and Python
reads it through cffi (crslab/world/world_facts.py) instead of writing it again: the world row's
columns, the fixtures' sensor order, the egg's flattening, the peg's depth, the groove's nearest
segment and the contest's rules. A scan of crslab's Python (its syntax trees) and C finds a copy
added back: a literal list of the row's or the sensors' names, a class or constant holding a rule's
number, a flattening share, a function working out the peg's depth or the groove's nearest
point. Each detector is shown to catch the copies crslab used to have (the scorecard's own rules
with a different peg depth, its own depth and nearest-segment code, board.py's column list,
scene.py's sensor list and flattening share)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from crslab.world import world_facts
from crslab.world.fixtures import ContestRules

ROOT = Path(__file__).resolve().parents[1]
PYTHON = sorted(p for p in (ROOT / "crslab").rglob("*.py"))
HOMES = {ROOT / "crslab" / "world" / "world_facts.py", ROOT / "crslab" / "world" / "fixtures.py"}
"""Where Python names C's facts (world_facts) and the rules' dataclass takes its defaults from it."""
COLUMN_NAMES = set(world_facts.WORLD_COLUMNS)
SENSOR_ONLY = {"scale", "obstacle_forearm", "obstacle_upper_arm"}
"""Sensor bodies that are no table of a world file: a list of fixture names holding one of them is
the sensors' order, not the file's tables."""
RULES = {f for f in ContestRules.__dataclass_fields__}


def _strings(node: ast.AST) -> list[str]:
    """The string constants a literal list, tuple, set or dict's keys hold (nested ones included)."""
    elements: list[ast.AST] = []
    if isinstance(node, ast.List | ast.Tuple | ast.Set):
        elements = list(node.elts)
    elif isinstance(node, ast.Dict):
        elements = [k for k in node.keys if k is not None]
    out = []
    for e in elements:
        if isinstance(e, ast.Constant) and isinstance(e.value, str):
            out.append(e.value)
        elif isinstance(e, ast.Tuple | ast.List):
            out += [x.value for x in e.elts if isinstance(x, ast.Constant) and isinstance(x.value, str)]
    return out


def _names_in(node: ast.AST) -> set[str]:
    return {n.attr for n in ast.walk(node) if isinstance(n, ast.Attribute)} | {
        n.id for n in ast.walk(node) if isinstance(n, ast.Name)}


def copies(source: str) -> list[tuple[int, str]]:
    """The world facts ``source`` (Python) writes again: (line, which fact)."""
    tree = ast.parse(source)
    found = []
    for node in ast.walk(tree):
        strings = set(_strings(node))
        if len(strings & COLUMN_NAMES) >= 4:
            found.append((node.lineno, "the world row's columns"))
        fixtures = {s.removesuffix("_force") for s in strings} & set(world_facts.FIXTURES)
        if len(fixtures) >= 4 and fixtures & SENSOR_ONLY:
            found.append((node.lineno, "the fixtures' sensor order"))
        if isinstance(node, ast.ClassDef):
            fields = {t.target.id for t in node.body if isinstance(t, ast.AnnAssign)
                      and isinstance(t.target, ast.Name) and t.value is not None}
            if len(fields & RULES) >= 2:
                found.append((node.lineno, "the contest's rules"))
        if isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            value = node.value
            literal = isinstance(value, ast.Constant) and isinstance(value.value, int | float) or (
                isinstance(value, ast.Tuple) and all(isinstance(e, ast.Constant) for e in value.elts))
            for t in targets:
                name = t.id if isinstance(t, ast.Name) else ""
                if literal and "FLAT" in name.upper():
                    found.append((node.lineno, "the egg's flattening"))
                if literal and name.isupper() and any(name.endswith(rule.upper()) for rule in RULES):
                    found.append((node.lineno, "the contest's rules"))
        if isinstance(node, ast.FunctionDef):
            names = _names_in(node)
            if {"top_z_m", "diameter_m"} <= names and "hypot" in names:
                found.append((node.lineno, "the peg's depth"))
            matmul = any(isinstance(n, ast.BinOp) and isinstance(n.op, ast.MatMult) for n in ast.walk(node))
            if "corners_xy_m" in names and "clip" in names and matmul:
                found.append((node.lineno, "the groove's nearest segment"))
    return sorted(set(found))


def test_crslab_writes_no_world_fact_twice():
    found = [f"{p.relative_to(ROOT)}:{line}: {what}" for p in PYTHON if p not in HOMES
             for line, what in copies(p.read_text())]
    assert found == []


def test_the_homes_name_the_facts_from_c_only():
    """world_facts.py holds no number of its own (everything is ``lib.``); fixtures.py's rules take
    their defaults from it."""
    tree = ast.parse((ROOT / "crslab" / "world" / "world_facts.py").read_text())
    numbers = [n.lineno for n in ast.walk(tree) if isinstance(n, ast.AnnAssign | ast.Assign)
               and isinstance(n.value, ast.Constant) and isinstance(n.value.value, int | float)]
    assert numbers == []
    f = world_facts
    assert ContestRules() == ContestRules(band_g=f.CONTEST_BAND_G, hold_s=f.CONTEST_HOLD_S,
                                          hold_tolerance_s=world_facts.CONTEST_HOLD_TOLERANCE_S,
                                          peg_min_depth_m=world_facts.CONTEST_PEG_MIN_DEPTH_M,
                                          peg_hold_s=world_facts.CONTEST_PEG_HOLD_S,
                                          groove_min_share=world_facts.CONTEST_GROOVE_MIN_SHARE,
                                          obstacle_around=world_facts.CONTEST_OBSTACLE_AROUND)


def test_c_holds_each_fact_in_one_file():
    """The rules' and the egg's numbers are defined in world_facts.h only; the row's names in
    world.c's column table only."""
    c_files = sorted((ROOT / "csrc").rglob("*.[ch]"))
    for path in c_files:
        text = path.read_text()
        if path.name != "world_facts.h":
            assert "static const double CRS_CONTEST_" not in text and "CRS_EGG_FLAT_SHARE =" not in text, path
        if path.name != "world.c" and "tests" not in path.parts:
            assert sum(f'"{name}"' in text for name in COLUMN_NAMES) < 4, path


# The copies crslab had before the world's facts moved to C (crslab/contest/scorecard.py,
# crslab/worker/board.py, crslab/world/scene.py, and the world's layout.py before its split): each is found.
OLD_COPIES = {
    "the contest's rules": '''
@dataclass(frozen=True)
class Rules:
    band_g: tuple[float, float] = (500.0, 1000.0)
    hold_s: float = 2.0
    peg_min_depth_m: float = 0.01
''',
    "the world row's columns": '''
WORLD_COLUMNS = {"peg_tip": 3, "egg_force": 1, "scale_g": 1, "egg_broken": 1, "hole_force": 1}
''',
    "the fixtures' sensor order": '''
FIXTURE_SENSORS = ("table", "hole", "obstacle", "groove", "egg", "scale")
''',
    "the egg's flattening": '''
EGG_FLAT = 0.2
''',
    "the peg's depth": '''
def _peg(world, rules, t, dt, tip):
    hole = world.hole
    cx, cy = hole.center_xy_m
    inside = np.hypot(tip[:, 0] - cx, tip[:, 1] - cy) <= hole.diameter_m / 2
    depth = np.where(inside, np.maximum(hole.top_z_m - tip[:, 2], 0.0), 0.0)
''',
    "the groove's nearest segment": '''
def _groove(world, tip):
    corners = np.asarray(world.groove.corners_xy_m)
    for a, b in zip(corners[:-1], corners[1:]):
        u = np.clip(((tip - a) @ (b - a)) / ((b - a) @ (b - a)), 0.0, 1.0)
''',
}


@pytest.mark.parametrize("fact", sorted(OLD_COPIES))
def test_a_copy_added_back_is_found(fact):
    assert [what for _, what in copies(OLD_COPIES[fact])] == [fact]


def test_the_world_file_s_own_lists_are_no_copy():
    """The world file's tables in its order (World.fixtures), a contact expectation's fixtures, the
    few quantities an expectation may bound are the file's and the scenario's, not the sensors'
    order or the row: not reported."""
    assert copies('TABLES = ("table", "hole", "obstacle", "groove", "egg")\n') == []
    assert copies('RANGES = {"egg_force": 1, "scale_g": 2, "peg_depth": 3}\n') == []
