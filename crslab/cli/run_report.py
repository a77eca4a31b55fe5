"""What ``crslab sim`` and ``crslab debug`` say on stderr once a run has ended (``record`` and
``check`` say its notices too): the summary line (or ``--json``), lab()'s cost against its
budget, the motor board's cut-outs and the safety envelope's trips (the framework's hold taking
over from the lab), and one line per thing the user should know (a NaN torque, a transmit ring
that overflowed, printf that went nowhere, a failed expectation).
"""

from __future__ import annotations

import sys
from pathlib import Path

from crslab._bindings import constants
from crslab.framework_facts import SCI_TX_FIFO_CHARS, SERIAL_CHARS_PER_MS, TICKS_PER_S
from crslab.generations import Generation
from crslab.lab.print_trigger import missing_printing_notice
from crslab.run.budget import cost_text, lab_cost
from crslab.run.status import RunResult, RunStatus
from crslab.scenario.expect_events import summary_text
from crslab.untrusted_text import for_terminal
from crslab.worker.run_stats import RunStats


def summary(result: RunResult, wall_s: float) -> dict:
    """The end-of-run numbers: time, lab()'s cost, NaN and long-line notices."""
    st = result.stats
    return {
        "status": result.status,
        "message": result.message,
        "simulated_s": result.end_tick / TICKS_PER_S,
        # a lab() call that hung was never measured: the summary says so, not "0 over the budget"
        **({"hung_tick": result.end_tick} if result.status is RunStatus.HUNG
           and "hung: lab() did not return" in result.message else {}),
        "wall_s": round(wall_s, 3),
        "lab_calls": st.lab_calls,
        **lab_cost(st),
        "nan_first_tick": st.nan_first_tick,
        "nan_first_tau": st.nan_first_joint,
        "nan_count": st.nan_count,
        "serial_dropped": st.serial_dropped,
        "tx_ring_dropped": st.tx_dropped,
        "tx_ring_first_drop_tick": st.tx_first_drop_tick,
        "console_bytes": st.console_bytes,
        "motor_board": st.motor_board,
        "motor_board_cutouts": st.motor_board_cutouts,
        "safety_trips": st.safety_trips,
        "safety_first_tick": st.safety_first_tick,
        "safety_ticks": st.safety_ticks,
        "expectations_met": sum(e.met for e in result.expectations),
        "expectations_failed": len(result.failed_expectations),
        "expectations_not_reached": sum(not e.reached for e in result.expectations),
        "expectations": [e.as_dict() for e in result.expectations],
    }


def summary_line(info: dict) -> str:
    """The end-of-run summary in one line.

    >>> summary_line({"simulated_s": 25.0, "wall_s": 0.5, "lab_calls": 10, "lab_cost_mean": 1234.0,
    ...               "lab_cost_unit": "instructions", "lab_cost_max": 5678.0, "lab_max_tick": 4100,
    ...               "over_budget": 2, "over_budget_ticks": [5000, 6000], "budget": 75000,
    ...               "motor_board": "piccolo", "motor_board_cutouts": 1})
    '25.000 s simulated in 0.50 s; lab() x10: mean 1,234 instructions, max 5,678 instructions (tick ...'
    >>> summary_line({"simulated_s": 0.4, "wall_s": 0.1, "lab_calls": 400, "lab_cost_mean": 2.5,
    ...               "lab_cost_unit": "us", "lab_cost_max": 9.0, "lab_max_tick": 7, "over_budget": 0,
    ...               "over_budget_ticks": [], "budget": 500.0})
    '0.400 s simulated in 0.10 s; lab() x400: mean 2.5 us, max 9.0 us (tick 7); 0 over the budget of 500 us'
    >>> summary_line({"simulated_s": 5.1, "wall_s": 2.0, "lab_calls": 5100, "lab_cost_mean": 900.0,
    ...               "lab_cost_unit": "instructions", "lab_cost_max": 950.0, "lab_max_tick": 7,
    ...               "over_budget": 0, "over_budget_ticks": [], "budget": 75000,
    ...               "hung_tick": 5100}).split("; ")[2]
    'the call at tick 5100 did not return (not counted above)'
    >>> summary_line({"simulated_s": 1.0, "wall_s": 0.1, "lab_calls": 0, "motor_board": "piccolo",
    ...               "motor_board_cutouts": 2, "expectations_met": 1, "expectations_failed": 1,
    ...               "expectations_not_reached": 0, "expectations": [{}, {}]})
    '1.000 s simulated in 0.10 s; motor board: 2 cut-outs; expectations: 1 met, 1 failed'
    >>> summary_line({"simulated_s": 15.0, "wall_s": 1.0, "lab_calls": 0, "safety_trips": 1,
    ...               "safety_first_tick": 5123, "safety_ticks": 9877}).split("; ")[1].split(": ")
    ['the arm left the safety envelope at tick 5123 (t = 5.123 s)', "the framework's hold took over \
from lab() (once, 9,877 ticks in all)"]

    """
    line = f"{info['simulated_s']:.3f} s simulated in {info['wall_s']:.2f} s"
    if info["lab_calls"]:
        line += "; " + cost_text(info)
    if info.get("motor_board", "none") != "none":
        n = info.get("motor_board_cutouts", 0)
        line += f"; motor board: {n} cut-out{'' if n == 1 else 's'}"
    if info.get("safety_trips"):
        n, t = info["safety_trips"], info["safety_first_tick"]
        times = "once" if n == 1 else f"{n} times"
        line += (f"; the arm left the safety envelope at tick {t} (t = {t / TICKS_PER_S:.3f} s): the "
                 f"framework's hold took over from lab() ({times}, {info['safety_ticks']:,} ticks in all)")
    if info.get("expectations"):
        line += "; " + summary_text(info["expectations_met"], info["expectations_failed"],
                                    info["expectations_not_reached"])
    return line


def lost_serial_notice(lab_name: str, stats: RunStats) -> str | None:
    """The warning for bytes that left the board but never reached the transcript, if any were lost.

    >>> lost_serial_notice("lab.c", RunStats(serial_dropped=925696)).split("; ")[1]
    'the 925696 bytes after that are missing from the transcript'
    """
    dropped = stats.serial_dropped
    if not dropped:
        return None
    c = constants
    return (f"warning: {lab_name}'s serial line carried more within one chunk of ticks than crslab keeps "
            f"({c.CRS_SERIAL_CAPACITY} bytes or {c.CRS_MARK_CAPACITY} ticks); "
            f"the {dropped} bytes after that are missing from the transcript")


def print_run_notes(prefix: str, lab_name: str, result: RunResult, generation: Generation) -> None:
    """On stderr after a run (``crslab sim`` and ``crslab debug``): its :func:`notices` and its
    failed scenario expectations, one line each."""
    for line in notices(lab_name, result.stats, generation, result.lab_file):
        print(f"{prefix}{for_terminal(line)}", file=sys.stderr)
    for expectation in result.failed_expectations:
        for line in expectation.lines():
            print(f"{prefix}expectation failed: {for_terminal(line)}", file=sys.stderr)


def notices(lab_name: str, stats: RunStats, generation: Generation, source: Path | None = None) -> list[str]:
    """One-line warnings about the run (printed on stderr); ``source``, the lab file, names the
    function a lab that triggers printing without a ``printing()`` probably meant."""
    out = []
    if source is not None and stats.lab_symbols:  # a run's: every lab that ran has its bits
        try:
            text = source.read_bytes().decode("utf-8", "replace")
        except OSError:
            text = ""
        missing = missing_printing_notice(
            lab_name, text, has_printing=bool(stats.lab_symbols & constants.CRS_LAB_HAS_PRINTING),
            triggers=stats.print_triggers, generation=generation)
        if missing:
            out.append(missing)
    lost = lost_serial_notice(lab_name, stats)
    if lost:
        out.append(lost)
    if stats.console_bytes > 0:
        out.append(f"note: {lab_name} wrote {stats.console_bytes} bytes with printf, puts or the like: "
                   "on the board they go to Code Composer Studio's console, not to Tera Term, and crslab "
                   "does not show them (serial_printf(&SerialA, ...) prints to Tera Term)")
    if stats.nan_first_tick >= 0:
        t = stats.nan_first_tick
        out.append(f"warning: {lab_name} returned a NaN or Inf in tau{stats.nan_first_joint} at tick {t} "
                   f"(t = {t / TICKS_PER_S:.3f} s); no torque was applied on that joint for that tick "
                   f"({stats.nan_count} such torques in all)")
    if stats.tx_dropped > 0:
        t = stats.tx_first_drop_tick
        out.append(f"warning: {lab_name} printed faster than the serial line sends "
                   f"({SERIAL_CHARS_PER_MS:g} characters per ms): {stats.tx_dropped} characters did not "
                   f"fit the board's {generation.tx_ring_chars}-byte transmit ring (and "
                   f"{SCI_TX_FIFO_CHARS}-byte FIFO) and were dropped, as on the real board; the first at "
                   f"tick {t} (t = {t / TICKS_PER_S:.3f} s)")
    return out


