"""Watched variables (#pragma DATA_SECTION) of a running lab, read and written between ticks."""

import pytest

from crslab.lab.watched import find_watched
from crslab.run.api import make_config
from crslab.run.board_run import BoardRun
from crslab.sinks.memory import MemorySink


def test_find_watched_handles_types_arrays_and_comments():
    src = """
    // #pragma DATA_SECTION(commented, ".my_vars")
    #pragma DATA_SECTION(gain, ".my_vars")
    float gain = 2.5;   /* Kp */
    #pragma DATA_SECTION(mode, ".my_vars")
    int mode=3;
    #pragma DATA_SECTION(samples, ".my_arrs")
    long samples[ 20 ];
    #pragma DATA_SECTION(nodecl, ".my_vars")
    """
    got = [(v.name, v.ctype, v.length, v.initial, v.section) for v in find_watched(src)]
    assert got == [("gain", "float", None, "2.5", ".my_vars"), ("mode", "int", None, "3", ".my_vars"),
                   ("samples", "long", 20, None, ".my_arrs")]


def test_set_whattoprint_changes_the_next_print_and_get_reads_arrays():
    with BoardRun(make_config()) as sim:
        sim.run(4700)
        arr = sim.get("theta2array")
        # the lab saves theta2motor every 50 calls: calls 0, 50, ..., 550 by tick 4700
        assert len(arr) == 100 and sum(1 for v in arr if abs(v + 0.42) < 1e-3) == 12
        sim.set("whattoprint", 1)
        out = MemorySink()
        sim.run(5200, out)
        assert out.calls == [(5100, b"I love robotics\n\r")]
        # the line leaves the board at 11.52 characters per ms from the print's tick on
        assert out.sent == [(5100, b"I love robo"), (5101, b"tics\n\r")]
        sim.set("theta1array", 7.5, index=3)
        assert sim.get("theta1array")[3] == 7.5
        with pytest.raises(KeyError, match="not a watched"):
            sim.set("mycount", 1)
        with pytest.raises(KeyError, match="give an index"):
            sim.set("theta1array", 1)
