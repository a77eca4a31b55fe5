"""The docs' times are the runs' times: debugging.md's session shows the tour's length as
``crslab debug`` says it, and first-lab.md's offsets paragraph the times the lab1_offsets scenario's
hand starts and arrives."""

import re
from pathlib import Path

from crslab.cli.debug_commands import DebugPlan, introduction
from crslab.scenario.hand_events import HandMove
from crslab.scenario.load import load_scenario

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_debugging_md_s_session_says_what_crslab_debug_says_for_the_tour():
    shown = re.search(r"^crslab debug: mylab\.c .*$", (DOCS / "debugging.md").read_text(), re.MULTILINE)[0]
    tour = load_scenario("tour")
    said = introduction(DebugPlan(break_tick=5000), lab=Path("mylab.c"), scenario_name="tour",
                        end_tick=tour.end_tick, first_lab_tick=4100, speed=None).splitlines()[0]
    assert shown == said


def test_first_lab_md_s_offsets_times_are_the_scenario_s():
    text = " ".join((DOCS / "first-lab.md").read_text().split())
    moves = [e for e in load_scenario("lab1_offsets").events if isinstance(e, HandMove)][:2]
    (start1, there1), (start2, there2) = [(e.tick // 1000, (e.tick + e.duration_ticks) // 1000)
                                          for e in moves]
    assert (f"At {start1} s the hand starts moving the arm to motor zero and holds it there from {there1} s"
            in text)
    assert f"At {start2} s it moves on to DH zero, the arm stretched level, there from {there2} s" in text
