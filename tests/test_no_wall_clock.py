"""No test synchronizes on wall time: no sleeps and no clock readings in tests/, except in
``tests/waiting.py``, whose helpers wait on events (a line on a pipe, a process's exit) with a
timeout only as a guard against hanging. Speed is measured by ``make bench``, never asserted here."""

import re
from pathlib import Path

TESTS = Path(__file__).resolve().parent
ALLOWED = {TESTS / "waiting.py", Path(__file__).resolve()}
CLOCK = re.compile(r"\btime\.(sleep|monotonic|monotonic_ns|perf_counter|perf_counter_ns|time|time_ns)\b"
                   r"|\bfrom\s+time\s+import\b|\basyncio\.sleep\b")


def wall_clock_uses(text: str) -> list[str]:
    """``line: code`` of every sleep or clock reading in ``text`` (code, comments and strings alike:
    a script a test runs counts too)."""
    return [f"{n}: {line.strip()}" for n, line in enumerate(text.splitlines(), 1) if CLOCK.search(line)]


def test_the_check_finds_sleeps_and_clocks():
    sample = ("import time\nstart = time.monotonic()\ntime.sleep(0.2)\nx = 'time.time()'\n"
              "from time import sleep\nawait asyncio.sleep(1)\nend_time = 3\nimport datetime\n")
    assert [u.split(":")[0] for u in wall_clock_uses(sample)] == ["2", "3", "4", "5", "6"]


def test_no_test_sleeps_or_reads_the_clock():
    found = {str(p.relative_to(TESTS)): uses for p in sorted(TESTS.rglob("*.py"))
             if p.resolve() not in ALLOWED and (uses := wall_clock_uses(p.read_text()))}
    assert not found, ("tests must wait on events, not wall time (use tests/waiting.py): "
                       + "; ".join(f"{name} line {use}" for name, uses in found.items() for use in uses))
