"""The first run explains itself: before the first tick one stderr paragraph names the lab and the
scenario (and, for crslab's own Lab 1, what its three lines are); scenario events are announced on
stderr when the run reaches them, between the lines printed before and after; none of it reaches
stdout or the transcript, and --quiet turns it off."""

import itertools
import subprocess
import sys
from pathlib import Path

LABS = Path(__file__).parent / "labs"
PRINT_TICKS = range(4100, 10_000, 500)  # Lab 1 prints three lines at each
EVENTS = {5000: "crslab sim: t = 5.0 s: hand to motor (0.00, 0.00, 0.00) = DH (0.00, -90.00, 90.00) deg "
                "over 2 s (there at t = 7.0 s)",
          9500: "crslab sim: t = 9.5 s: hand to motor (0.00, 90.00, 0.00) = DH (0.00, 0.00, 0.00) deg "
                "over 2 s (there at t = 11.5 s)"}


def sim(*args, merged=False, cwd=None):
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--no-stdin", *map(str, args)],
                          capture_output=not merged, stdout=subprocess.PIPE if merged else None,
                          stderr=subprocess.STDOUT if merged else None, text=True, timeout=120, cwd=cwd)


def test_events_come_out_between_the_lines_printed_before_and_after_them(tmp_path):
    """stdout and stderr into one pipe: the order is what a terminal shows."""
    t = tmp_path / "t.txt"
    r = sim("--speed", "8", "--duration", "10", "--transcript", t, merged=True)
    assert r.returncode == 0, r.stdout
    lines = r.stdout.splitlines()
    # the paragraph first, then prints at 4.1 ... 9.6 s with each event before the first print after it
    assert lines[0] == "crslab sim: lab1_kinematics.c on scenario tour for 10.0 s, at 8x real time."
    paragraph = " ".join([lines[0], *itertools.takewhile(lambda line: line.startswith("  "), lines[1:])])
    assert "theta1 theta2 theta3 (deg)" in paragraph and "x y z (in)" in paragraph
    body = [line for line in lines if not line.startswith("  ")][1:-1]  # without the summary line
    expected_order = []
    for tick in PRINT_TICKS:
        expected_order += [EVENTS[e] for e in sorted(EVENTS) if tick - 500 < e <= tick]
        expected_order += ["<print>"] * 3
    assert [line if line.startswith("crslab sim:") else "<print>" for line in body] == expected_order
    assert lines[-1].startswith("crslab sim: 10.000 s simulated")
    # the transcript and stdout hold only what the board printed
    raw = t.read_bytes()
    assert raw.count(b"\n\r") == 3 * len(PRINT_TICKS) and b"crslab" not in raw and b"hand to" not in raw


def test_stdout_and_the_transcript_are_the_same_with_and_without_quiet(tmp_path):
    loud, quiet = tmp_path / "loud.txt", tmp_path / "quiet.txt"
    a = sim("--fast", "--duration", "10", "--transcript", loud)
    b = sim("--fast", "--duration", "10", "--transcript", quiet, "--quiet")
    assert a.returncode == b.returncode == 0
    assert loud.read_bytes() == quiet.read_bytes() and a.stdout == b.stdout
    assert a.stdout == loud.read_bytes().decode().replace("\n\r", "\n")
    assert [line for line in a.stderr.splitlines() if ": t = " in line] == [EVENTS[5000], EVENTS[9500]]
    quiet_err = b.stderr.splitlines()
    assert len(quiet_err) == 1 and quiet_err[0].startswith("crslab sim: 10.000 s simulated")


def test_a_students_lab_is_introduced_without_guessing_its_columns(tmp_path):
    r = sim("--fast", "--duration", "5", "--lab", LABS / "lab1_own_ik.c", "--scenario", "hands_off",
            "--no-startup-delay")
    assert r.returncode == 0, r.stderr
    paragraph = r.stderr.split("crslab sim: 5.000 s simulated")[0]
    assert paragraph.startswith("crslab sim: lab1_own_ik.c on scenario hands_off for 5.0 s, as fast as it "
                                "can.")
    assert "from the first tick" in paragraph and "exactly as Tera Term shows it" in paragraph
    assert "theta1" not in paragraph and ": t = " not in paragraph  # hands_off has no events
