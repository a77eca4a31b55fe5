"""The students' path to the contest (issue 37): a run in a world with fixtures is hands off unless
a scenario is named; ``crslab world`` lists the built-in worlds, prints one to copy and checks a
bench's file; ``crslab grade --help`` says which defaults ``--contest`` changes."""

from __future__ import annotations

import dataclasses
import subprocess
import sys

from crslab.run.api import make_config
from crslab.world import load_world, world_file


def crslab(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=300, cwd=cwd)


def test_a_run_in_a_world_is_hands_off_unless_a_scenario_is_named():
    assert make_config(None, world="contest").scenario.name == "hands_off"
    assert make_config(None, world=load_world("contest")).scenario.name == "hands_off"
    assert make_config(None, "tour", world="contest").scenario.name == "tour"
    assert make_config(None).scenario.name == "tour"
    assert make_config(None, world="none").scenario.name == "tour"


def test_crslab_sim_in_the_contest_world_says_it_runs_hands_off(tmp_path):
    r = crslab("sim", "--world", "contest", "--fast", "--duration", "0.2", "--no-stdin", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "on scenario hands_off" in r.stderr.splitlines()[0]


def test_world_list_show_and_check(tmp_path):
    r = crslab("world", "list", cwd=tmp_path)
    assert r.returncode == 0 and r.stdout.splitlines() == [
        "none       nothing: free air (the default)", "contest    table, hole, obstacle, groove, egg"]
    r = crslab("world", "show", "contest", cwd=tmp_path)
    assert r.returncode == 0 and r.stdout == world_file("contest")[0].read_text()
    bench = tmp_path / "bench.toml"
    bench.write_text(r.stdout)
    assert dataclasses.replace(load_world(bench), source="contest") == load_world("contest")
    r = crslab("world", "check", bench, cwd=tmp_path)
    assert r.returncode == 0 and r.stdout == f"{bench}: world 'contest': table, hole, obstacle, groove, egg\n"
    # a bench's mistake: one line naming the file, its line and the key
    broken = tmp_path / "broken.toml"
    broken.write_text(bench.read_text().replace("[egg]", "[egg]\nheight = 2", 1))
    r = crslab("world", "check", broken, cwd=tmp_path)
    assert r.returncode == 2 and r.stdout == ""
    [line] = r.stderr.splitlines()
    assert line.startswith(f"crslab world: {broken}:") and "egg.height: unknown key" in line
    r = crslab("world", "show", "mars", cwd=tmp_path)
    assert r.returncode == 2 and "no built-in world 'mars' (built-ins: none, contest)" in r.stderr


def test_grade_help_says_the_defaults_contest_changes(tmp_path):
    text = " ".join(crslab("grade", "--help", cwd=tmp_path).stdout.split())
    assert ("--contest changes these defaults: --world contest (not none), --scenario hands_off (not tour), "
            "--duration until each arm comes to rest (not the scenario's end), --offsets each lab's own "
            "offset_Enc2_rad and offset_Enc3_rad (not crslab's arm's)") in text
    assert "with --contest: default contest" in text and "with --contest: default hands_off" in text
