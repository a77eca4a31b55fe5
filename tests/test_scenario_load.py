"""Scenario files: every event kind parses to its dataclass; every mistake is one error naming
the file, the line and the key; the built-ins and the documented examples all load."""

import importlib
import math
import pkgutil
import re
import subprocess
import sys
from pathlib import Path

import pytest

from crslab import crs, scenario
from crslab.lab.build import build_lab
from crslab.plant.model_files import COURSE_END_MASS_KG
from crslab.scenario.event import Event
from crslab.scenario.fault_events import EncoderGlitch, JointFault, WristEstop
from crslab.scenario.hand_events import HandMove, HandRelease
from crslab.scenario.kinds import EVENT_CLASSES, EVENT_KINDS, kinds_of
from crslab.scenario.lab_events import SetVariable
from crslab.scenario.load import (
    BUILTIN_DIR,
    ScenarioError,
    builtin_names,
    check_lab,
    describe_builtins,
    load_scenario,
    parse_scenario,
)
from crslab.scenario.plant_events import EndMass, FrictionScale

ROOT = Path(__file__).resolve().parents[1]
LABS = ROOT / "tests" / "labs"
DOCS = ROOT / "docs" / "scenarios.md"


def crslab(*args):
    return subprocess.run([sys.executable, "-m", "crslab", *args], capture_output=True, text=True, timeout=60)


def parse(text, name="s.toml"):
    return parse_scenario(text, Path(name))


def one_event(body, end=30.0, seed=None):
    head = f"end = {end}\n" + (f"seed = {seed}\n" if seed is not None else "")
    return parse(head + "[[event]]\n" + body).events


def test_every_kind_parses_to_its_dataclass():
    s = load_scenario(str(ROOT / "tests" / "data" / "every_event_kind.toml"))
    kinds = {e.kind for e in s.events}
    # glitches expand into glitch events; the rest keep their own kind
    assert kinds == set(EVENT_KINDS) - {"glitches"}
    assert s.seed == 7 and s.end_tick == 20000
    np_rest = s.rest_motor_rad
    assert np_rest == (0.0, -0.40, 0.26)
    assert [e.tick for e in s.events] == sorted(e.tick for e in s.events)


def test_hand_targets_and_hold():
    (move,) = one_event('at = 5\nkind = "hand"\nmotor_deg = [0, 90, 0]\nduration = 2\n')
    assert move == HandMove(tick=5000, target_dh_rad=(0.0, 0.0, 0.0), duration_ticks=2000)
    (move,) = one_event('at = 5\nkind = "hand"\ndh_deg = [10, -20, 30]\n')
    assert move.duration_ticks == 1000
    assert move.target_dh_rad == pytest.approx(tuple(math.radians(v) for v in (10, -20, 30)))
    (move,) = one_event('at = 5\nkind = "hand"\nxyz_in = [12, 3, 15]\n')
    assert crs.fk(crs.dh_to_motor(move.target_dh_rad)) == pytest.approx([12, 3, 15])
    move, release = one_event('at = 5\nkind = "hand"\npose = "rest"\nduration = 1.5\nhold = 2\n')
    assert move.target_dh_rad is None and release == HandRelease(tick=8500)


def test_writes_and_simulink_inputs():
    (s,) = one_event('at = 6\nkind = "set"\nvar = "theta1array"\nindex = 3\nvalue = 0.25\n')
    assert s == SetVariable(tick=6000, name="theta1array", value=0.25, index=3)
    (u,) = one_event('at = 6\nkind = "simulink"\nvalues = [100, -20, 5]\n')
    assert u.values == ((1, 100), (2, -20), (3, 5))
    (u,) = one_event('at = 6\nkind = "simulink"\ninput = 7\nvalue = -32768\n')
    assert u.values == ((7, -32768),)


def test_plant_changes():
    s = parse('end = 9\n[plant]\nrest_motor_deg = [0, -24, 13]\nend_mass_kg = "course"\nfriction_scale = 0.5')
    assert s.rest_motor_rad == pytest.approx((0.0, math.radians(-24), math.radians(13)))
    assert s.events == (EndMass(tick=0, kg=COURSE_END_MASS_KG), FrictionScale(tick=0, scale=0.5))
    (m,) = one_event('at = 10\nkind = "end_mass"\nkg = 0.5\n')
    assert m == EndMass(tick=10000, kg=0.5)


def test_faults_with_joints_lists_and_until():
    on, off = one_event('at = 7\nkind = "noise"\ncounts = 40\njoints = [2, 3]\nuntil = 9\n')
    assert on.counts == (0.0, 40.0, 40.0) and off.counts == (0.0, 0.0, 0.0) and off.tick == 9000
    (g,) = one_event('at = 7.5\nkind = "glitch"\ncounts = [1, -2, 3]\n')
    assert g == EncoderGlitch(tick=7500, counts=(1, -2, 3))
    stuck, free = one_event('at = 11\nkind = "stuck_encoder"\njoint = 1\nuntil = 12\n')
    assert stuck == JointFault(tick=11000, fault="stuck_encoder", joints=(1,))
    assert free == JointFault(tick=12000, fault="stuck_encoder", joints=(1,), on=False)
    (dead,) = one_event('at = 13\nkind = "dead_motor"\n')
    assert dead == JointFault(tick=13000, fault="dead_motor", joints=(1, 2, 3))
    (stop,) = one_event('at = 15\nkind = "estop"\nwrist_rad = 0.05\n')
    assert stop == WristEstop(tick=15000, wrist_rad=0.05)


def test_random_glitches_follow_the_seed():
    body = 'at = 5\nkind = "glitches"\nuntil = 25\nrate_hz = 3\ncounts = 3000\njoints = [1, 2]\n'
    a, b, c = one_event(body, seed=4), one_event(body, seed=4), one_event(body, seed=5)
    assert a == b and a != c
    assert 30 <= len(a) <= 90  # about 60 at 3 per second over 20 s
    assert all(5000 <= g.tick < 25000 and sorted(map(abs, g.counts)) == [0, 0, 3000] and g.counts[2] == 0
               for g in a)
    noise = 'at = 5\nkind = "noise"\ncounts = 3\n'
    assert one_event(noise, seed=4)[0].rng_state == one_event(noise, seed=4)[0].rng_state
    assert one_event(noise, seed=4)[0].rng_state != one_event(noise, seed=5)[0].rng_state


MALFORMED = [
    # (body after 'end = 30', expected "line: key: ..." start)
    ('[[event]]\nat = 5\nkind = "nap"\n', "4: kind: unknown event kind 'nap'"),
    ('[[event]]\nat = 5\n', "2: kind: missing"),
    ('[[event]]\nkind = "release"\n', "2: at: missing"),
    ('[[event]]\nat = "five"\nkind = "release"\n', "3: at: must be a number"),
    ('[[event]]\nat = 35\nkind = "release"\n', "3: at: 35 s is after the end (30 s)"),
    ('[[event]]\nat = 5\nkind = "release"\nduration = 2\n', "5: duration: unknown key"),
    ('[[event]]\nat = 5\nkind = "hand"\nmotor_deg = [0, 0]\n', "5: motor_deg: must be a list of three"),
    ('[[event]]\nat = 5\nkind = "hand"\n', "2: motor_deg|dh_deg|xyz_in|pose: give exactly one target"),
    ('[[event]]\nat = 5\nkind = "hand"\nxyz_in = [40, 0, 10]\n', "5: xyz_in: target"),
    ('[[event]]\nat = 5\nkind = "hand"\npose = "home"\n', "5: pose: the only named pose"),
    ('[[event]]\nat = 5\nkind = "hand"\npose = "rest"\nhold = -1\n', "6: hold: must be at least 0"),
    ('[[event]]\nat = 5\nkind = "set"\nvalue = 1\n', "2: var: missing"),
    ('[[event]]\nat = 5\nkind = "set"\nvar = "a b"\nvalue = 1\n', "5: var: must be a C variable name"),
    ('[[event]]\nat = 5\nkind = "set"\nvar = "x"\nvalue = "one"\n', "6: value: must be a number"),
    ('[[event]]\nat = 5\nkind = "set"\nvar = "x"\nvalue = 1\nindex = -1\n', "7: index: must be from 0"),
    ('[[event]]\nat = 5\nkind = "simulink"\nvalues = [1, 2, 3, 4, 5, 6, 7, 8]', "5: values: must be a list"),
    ('[[event]]\nat = 5\nkind = "simulink"\nvalues = [40000]\n', "5: values: must be a list of 1 to 7"),
    ('[[event]]\nat = 5\nkind = "simulink"\ninput = 8\nvalue = 1\n', "5: input: must be from 1 to 7"),
    ('[[event]]\nat = 5\nkind = "end_mass"\nkg = "lots"\n', "5: kg: must be a number of kg or \"course\""),
    ('[[event]]\nat = 5\nkind = "end_mass"\n', "2: kg: missing"),
    ('[[event]]\nat = 5\nkind = "friction"\nscale = -1\n', "5: scale: must be at least 0"),
    ('[[event]]\nat = 5\nkind = "noise"\ncounts = -3\n', "5: counts: must be at least 0"),
    ('[[event]]\nat = 5\nkind = "noise"\ncounts = [1, 2]\n', "5: counts: must be a list of three"),
    ('[[event]]\nat = 5\nkind = "noise"\ncounts = [1, 2, 3]\njoint = 1\n', "5: counts: a list gives"),
    ('[[event]]\nat = 5\nkind = "noise"\ncounts = 3\nuntil = 4\n', "6: until: must be later than at"),
    ('[[event]]\nat = 5\nkind = "glitch"\ncounts = 2.5\n', "5: counts: must be whole numbers"),
    ('[[event]]\nat = 5\nkind = "glitches"\nrate_hz = 1\ncounts = 9\n', "2: until: missing"),
    ('[[event]]\nat = 5\nkind = "glitches"\nuntil = 6\nrate_hz = 0\ncounts = 9', "6: rate_hz: must be more"),
    ('[[event]]\nat = 5\nkind = "stuck_encoder"\njoint = 4\n', "5: joint: must be from 1 to 3, got 4"),
    ('[[event]]\nat = 5\nkind = "dead_motor"\njoints = [0, 1]\n', "5: joints: must be a list of joint"),
    ('[[event]]\nat = 5\nkind = "dead_motor"\njoint = 1\njoints = [2]\n', "6: joints: give joint or joints"),
    ('[[event]]\nat = 5\nkind = "estop"\nwrist_rad = "far"\n', "5: wrist_rad: must be a number"),
    ('[plant]\nrest_motor_rad = [0, -0.4]\n', "3: rest_motor_rad: must be a list of three"),
    ('[plant]\nrest_motor_deg = [0, 200, 0]\n', "3: rest_motor_deg: each angle"),
    ('[plant]\nfriction = 2\n', "3: friction: unknown key"),
    ('seed = -1\n', "2: seed: must be from 0"),
    ('seed = ' + '9' * 400 + '\n', "2: seed: a whole number of 400 digits is too large"),
    ('[[event]]\nat = 5\nkind = "end_mass"\nkg = 10.5\n', "5: kg: must be at most 10, got 10.5"),
    ('[plant]\nend_mass_kg = 1e300\n', "3: plant.end_mass_kg: 1e300 is too large a number"),
    ('[[event]]\nat = 5\nkind = "friction"\nscale = 101\n', "5: scale: must be at most 100, got 101"),
    ('[[event]]\nat = 5\nkind = "push"\nforce_n = [0, 0, 1001]\n',
     "5: force_n: each component must be within +-1000 N, got [0.0, 0.0, 1001.0]"),
    ('[[event]]\nat = 5\nkind = "noise"\ncounts = 3\nuntil = 86401\n', "6: until: must be at most 86400"),
    ('[[event]]\nat = 1e-300\nkind = "estop"\n', "3: event.at: 1e-300 is too small a number"),
    ('[[event]]\nat = 5\nkind = "hand"\nmotor_deg = [[[[[[[[0]]]]]]]]\n',
     "5: event.motor_deg: nested too deep"),
    ('colour = "red"\n', "2: colour: unknown key"),
    ('[[event]]\nat = 5\nkind = "release"\n[[event]]\nat = 6\nkind = "hand"\ndh_deg = [0]\n',
     "8: dh_deg: must be a list of three"),
]


@pytest.mark.parametrize("body, expected", MALFORMED)
def test_a_malformed_file_gets_one_error_naming_file_line_and_key(body, expected):
    with pytest.raises(ScenarioError) as err:
        parse("end = 30\n" + body, "bad.toml")
    message = str(err.value)
    assert message.startswith("bad.toml:" + expected), message
    assert "\n" not in message


def test_bad_toml_and_missing_end_and_missing_file(tmp_path):
    with pytest.raises(ScenarioError, match=r"^bad.toml:2: not valid TOML"):
        parse('end = 3\nat = = 4\n', "bad.toml")
    with pytest.raises(ScenarioError, match=r"^bad.toml: end: missing$"):
        parse('name = "x"\n', "bad.toml")
    with pytest.raises(ScenarioError, match=r"no such scenario file or built-in \(built-ins: end_mass, "):
        load_scenario(str(tmp_path / "nowhere.toml"))


def test_writes_are_checked_against_the_labs_watched_variables(tmp_path):
    build = build_lab(LABS / "watch_inputs.c")
    ok = parse('end = 9\n[[event]]\nat = 5\nkind = "set"\nvar = "table"\nindex = 3\nvalue = 1\n')
    check_lab(ok, build)
    cases = [('var = "gain"\nindex = 0\n', "s.toml:5: index: gain is not an array in watch_inputs.c"),
             ('var = "table"\n', "s.toml:5: index: table has 4 elements in watch_inputs.c: give an index 0."),
             ('var = "table"\nindex = 4\n', "give an index 0..3"),
             ('var = "mode"\nvalue = 3e9\n', "s.toml:5: value: 3e+09 does not fit mode, int in watch_inputs"),
             ('var = "mycount"\n',
              "s.toml:5: var: mycount is not a watched (#pragma DATA_SECTION) variable of watch_inputs.c "
              "(watched: gain, mode, table)")]
    for body, expected in cases:
        value = "" if "value" in body else "value = 1\n"
        s = parse('end = 9\n[[event]]\nat = 5\nkind = "set"\n' + body + value)
        with pytest.raises(ScenarioError) as err:
            check_lab(s, build)
        assert expected in str(err.value)


def test_builtins_load_and_are_listed_one_line_each():
    names = builtin_names()
    assert {"tour", "hands_off", "lab1_offsets", "lab1_torque_signs", "lab2_steps", "end_mass"} <= set(names)
    for name in names:
        s = load_scenario(name)
        assert s.name == name and s.description and s.end_tick > 4100
    described = describe_builtins()
    assert described[0][0] == "tour" and len(described) == len(names)
    r = crslab("scenarios")
    assert r.returncode == 0
    lines = r.stdout.strip().splitlines()
    assert len(lines) == len(names) and lines[0].startswith("tour ") and "default" in lines[0]
    assert all(re.match(rf"{re.escape(n)} +\S", line) for (n, _), line in zip(described, lines))


def test_crslab_scenarios_file_prints_the_timeline_or_one_error(tmp_path):
    good = tmp_path / "s.toml"
    good.write_text('end = 9\nseed = 3\n[[event]]\nat = 5\nkind = "set"\nvar = "whattoprint"\nvalue = 1\n')
    r = crslab("scenarios", str(good))
    assert r.returncode == 0
    assert "   5.000 s  set whattoprint = 1  (line 6)" in r.stdout and "9.000 s  end (seed 3)" in r.stdout
    bad = tmp_path / "bad.toml"
    bad.write_text('end = 9\n[[event]]\nat = 5\nkind = "glitch"\njoint = 9\ncounts = 1\n')
    r = crslab("scenarios", str(bad))
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.strip() == f"crslab scenarios: {bad}:5: joint: must be from 1 to 3, got 9"


def test_every_example_in_the_docs_parses():
    text = DOCS.read_text()
    blocks = re.findall(r"```toml\n(.*?)```", text, flags=re.DOTALL)
    assert len(blocks) >= 14
    for block in blocks:
        if not re.search(r"^end\s*=", block, flags=re.MULTILINE):
            block = "end = 30.0\n" + block
        s = parse(block, "docs.toml")
        assert s.events or s.rest_motor_rad is not None
    # and every kind is documented with its own heading
    for kind in EVENT_KINDS:
        assert f"### `{kind}`" in text


def test_builtin_files_load_by_path_too():
    for path in BUILTIN_DIR.glob("*.toml"):
        assert load_scenario(str(path)).source == str(path)


def test_scenarios_are_data_that_never_import_the_simulator():
    code = ("import sys\nfrom crslab.scenario.load import load_scenario\n"
            "import crslab.scenario.kinds\ns = load_scenario('tour')\n"
            "print(sorted(m for m in sys.modules if m.startswith(('crslab.run', 'mujoco'))))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]"


def test_each_kind_is_one_class_that_parses_and_describes_itself():
    for kind, cls in EVENT_KINDS.items():
        assert kind in cls.kinds
        assert "parse" in cls.__dict__ and "describe" in cls.__dict__, cls.__name__
    another = type("AnotherGlitch", (Event,), {"kinds": ("glitch",)})
    with pytest.raises(TypeError, match="'glitch' is parsed by EncoderGlitch and AnotherGlitch"):
        kinds_of([*EVENT_CLASSES, another])


def test_every_event_class_of_the_scenario_package_is_registered_once():
    modules = [m.name for m in pkgutil.iter_modules(scenario.__path__) if m.name.endswith("_events")]
    for name in modules:
        importlib.import_module(f"crslab.scenario.{name}")
    defined, todo = set(), [Event]
    while todo:
        for sub in todo.pop().__subclasses__():
            todo.append(sub)
            if sub.__module__.startswith("crslab.scenario."):
                defined.add(sub)
    assert len(modules) == 6 and defined == set(EVENT_CLASSES)
    assert len(EVENT_CLASSES) == len(set(EVENT_CLASSES))
    # one class parses both joint faults; each event carries its own kind
    dead = one_event('at = 1\nkind = "dead_motor"\njoint = 2\nuntil = 2\n')
    assert [(e.kind, e.on, e.describe()) for e in dead] == [("dead_motor", True, "dead_motor joints 2 dead"),
                                                            ("dead_motor", False, "dead_motor joints 2 back")]
