"""The board's serial line (docs/framework.md section 6): serial_printf formats into a buffer of its
generation's size (a line that does not fit stops the run: the real board's memory is corrupt),
queues into the transmit ring (136 bytes on Gen B, 2048 on Gen A) in front of the SCI's 16-byte
FIFO and shift register, and the line sends 11.52 characters per ms (115200 baud, 8N1). What
does not fit the ring is dropped; the transcript carries what left, when it left, identically at
any speed.

The expected bytes and ticks come from a second model of the line written here with exact
fractions of a millisecond."""

import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest

from crslab.run.api import simulate

LABS = Path(__file__).parent / "labs"
BURSTS = LABS / "bursts_gen_b.c"
CHAR_MS = Fraction(10 * 1000, 115200)  # one 8N1 character at 115200 baud, in ms
FIFO_AND_SHIFT = 16 + 1


def serial_line_model(prints: list[tuple[int, bytes]], ring: int):
    """What leaves the board: (kept per print, sent as (tick, byte) per character, dropped, first
    drop tick). Each print happens at the start of its tick's millisecond; the ring holds what the
    FIFO and the shift register (17 characters) cannot take, after each print."""
    done: list[Fraction] = []  # when each queued character has fully left, in ms
    kept, sent, dropped, first_drop = [], [], 0, None
    for tick, data in prints:
        queued = [d for d in done if d > tick]
        in_ring = max(0, len(queued) - FIFO_AND_SHIFT)
        take = min(len(data), max(0, ring - in_ring))
        if take < len(data):
            dropped += len(data) - take
            first_drop = tick if first_drop is None else first_drop
        start = max([Fraction(tick)] + done[-1:])
        for i, byte in enumerate(data[:take]):
            end = start + (i + 1) * CHAR_MS
            done.append(end)
            sent.append((int(-(-end // 1)) - 1, byte))  # the tick during whose ms it ends
        kept.append((tick, data[:take]))
    return kept, sent, dropped, first_drop


def bursts(generation_b: bool) -> list[tuple[int, bytes]]:
    out = []
    for call in (0, 3, 2000):
        for line in (1, 2, 3, 4):
            text = f"burst at call {call:4d}, line {line}: {'the quick brown fox jumps':<30s}\n\r"
            assert len(text) == 60
            out.append((4100 + call, text.encode()))
    return out


def per_tick(sent: list[tuple[int, int]]) -> list[tuple[int, bytes]]:
    chunks: list[tuple[int, bytes]] = []
    for tick, byte in sent:
        if chunks and chunks[-1][0] == tick:
            chunks[-1] = (tick, chunks[-1][1] + bytes([byte]))
        else:
            chunks.append((tick, bytes([byte])))
    return chunks


@pytest.fixture(scope="module")
def gen_b_bursts():
    return simulate(BURSTS, "hands_off", duration_s=6.2)


def test_three_bursts_of_four_60_byte_lines_lose_characters_as_the_ring_would(gen_b_bursts):
    kept, sent, dropped, first_drop = serial_line_model(bursts(True), ring=136)
    # per print: its tick and what the ring took of it (burst 1: 60, 60, 33, 0 of 60 each)
    assert gen_b_bursts.calls == [(tick, data) for tick, data in kept if data]
    assert [len(d) for _, d in kept] == [60, 60, 33, 0, 34, 0, 0, 0, 60, 60, 33, 0]
    assert gen_b_bursts.stats.tx_dropped == dropped == 87 + 206 + 87
    assert gen_b_bursts.stats.tx_first_drop_tick == first_drop == 4100


def test_bytes_leave_the_board_at_11_52_characters_per_ms(gen_b_bursts):
    _, sent, _, _ = serial_line_model(bursts(True), ring=136)
    assert gen_b_bursts.sent == per_tick(sent)
    assert gen_b_bursts.sent[:2] == [(4100, b"burst at ca"), (4101, b"ll    0, lin")]  # 11, then 23 in all


def test_gen_a_has_room_for_every_burst_in_its_2048_byte_ring(tmp_path):
    lab = tmp_path / "bursts_gen_a.c"
    lab.write_text(BURSTS.read_text().replace('#include "F28335Serial.h"', "#include <coecsl.h>"))
    run = simulate(lab, "hands_off", duration_s=6.2)
    kept, sent, dropped, _ = serial_line_model(bursts(False), ring=2048)
    assert dropped == 0 and run.stats.tx_dropped == 0
    assert run.sent == per_tick(sent) and run.transcript == b"".join(d for _, d in bursts(False))


def test_the_same_run_sends_the_same_bytes_at_the_same_ticks_at_any_speed(gen_b_bursts):
    real_time = simulate(BURSTS, "hands_off", duration_s=6.2, speed=20.0)
    assert real_time.sent == gen_b_bursts.sent and real_time.calls == gen_b_bursts.calls


def crslab_sim(lab: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--lab", str(lab), "--scenario",
                           "hands_off", *args], capture_output=True, text=True, timeout=120)


def test_dropped_characters_are_reported_on_stderr():
    r = crslab_sim(BURSTS, "--duration", "6.2")
    assert r.returncode == 0
    assert ("crslab sim: warning: bursts_gen_b.c printed faster than the serial line sends (11.52 characters "
            "per ms): 380 characters did not fit the board's 136-byte transmit ring (and 16-byte FIFO) and "
            "were dropped, as on the real board; the first at tick 4100 (t = 4.100 s)"
            ) in r.stderr.splitlines()


def test_a_152_byte_gen_b_line_stops_the_run_naming_the_136_byte_buffer(tmp_path):
    transcript = tmp_path / "t.txt"
    r = crslab_sim(LABS / "long_line_gen_b.c", "--duration", "6", "--transcript", str(transcript))
    assert r.returncode == 3
    assert r.stderr.splitlines()[-1] == (
        "crslab sim: long_line_gen_b.c: a serial_printf in printing() at tick 5100 (t = 5.100 s) formatted "
        "152 characters; the board's 136-byte serial_printf buffer holds 135 and a terminating NUL, so this "
        "line overflows it and corrupts the board's memory")
    assert transcript.read_bytes() == b"call 0\n\rcall 500\n\r"  # what was printed before is kept
    assert "Traceback" not in r.stderr
