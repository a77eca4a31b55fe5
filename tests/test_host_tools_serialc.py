"""SerialC, the course's MATLAB protocol, against a real lab in its (sandboxed) worker: reads
return the current value of the lab's globals as the C28x holds them, writes take effect between
ticks, replies leave at the baud rate through the port's transmit ring (docs/host-tools.md,
"SerialC: a MATLAB message"). Requests are handed to the board as the bridge does
(``BoardRun.exchange``) between chunks; the expected bytes are the doc's worked vectors, or
struct packing of values the lab itself printed or stored."""

import struct
from pathlib import Path

import pytest

from crslab.host_tools.serial_protocols import read_request, write_request
from crslab.live.bridge import SerialBridge
from crslab.run.api import make_config
from crslab.run.board_run import BoardRun
from crslab.sinks.memory import MemorySink

LABS = Path(__file__).parent / "labs"
GEN_A_LAB, GEN_B_LAB = LABS / "host_tools_gen_a.c", LABS / "host_tools_gen_b.c"


@pytest.fixture(scope="module")
def gen_a_config():
    return make_config(GEN_A_LAB, "hands_off", startup_delay=False)


@pytest.fixture(scope="module")
def gen_b_config():
    return make_config(GEN_B_LAB, "hands_off", startup_delay=False)


def ask(sim, request: bytes, ticks: int = 10) -> bytes:
    """Hand ``request`` to SerialC now, run ``ticks`` more ticks, and take what came back."""
    assert sim.exchange("SerialC", request).taken == len(request)
    sim.run(sim.tick + ticks)
    return sim.exchange("SerialC", b"").sent


def test_gen_a_answers_the_worked_vectors_and_writes_reach_the_next_print(gen_a_config):
    mem = gen_a_config.build.memory
    out = MemorySink()
    with BoardRun(gen_a_config) as sim:
        sim.run(100, out)
        # whattoprint = 1.25 at 0xc816: docs/host-tools.md's first worked vector
        assert ask(sim, bytes.fromhex("2a 09 32 00 00 c8 16 00 01")) == bytes.fromhex("2a 04 33 00 00 a0 3f")
        # a read arrives during the tick it is handed over (9 bytes = 90 000 of 115 200 line units),
        # after that tick's lab(); its reply leaves at once: 2 bytes during that tick, 5 in the next
        sim.exchange("SerialC", read_request(0xC816, 1))
        sim.run(sim.tick + 1)
        assert sim.exchange("SerialC", b"").sent == bytes.fromhex("2a 04")
        sim.run(sim.tick + 1)
        assert sim.exchange("SerialC", b"").sent == bytes.fromhex("33 00 00 a0 3f")
        # 100 floats of timearray: the lab stored the time of each sample (every 50 ms)
        reply = ask(sim, read_request(mem.find("timearray").address, 100), ticks=40)
        assert reply[:3] == bytes([0x2A, 103, 0x33]) and len(reply) == 403
        assert struct.unpack("<100f", reply[3:])[:3] == (0.0, 50.0, 100.0)
        # write Kp1 = 40 (the little-endian '3'), then -2.5 big-endian with Gen A's '1'
        assert ask(sim, write_request(mem.find("Kp1").address, 40.0)) == b""
        sim.run(400, out)
        assert ask(sim, bytes.fromhex("2a 0b 31 00 00 c8 18 c0 20 00 00")) == b""
        sim.run(600, out)
        # matlabLock, right after the lab's .my_vars, was set to 1 by the reads
        assert ask(sim, read_request(0xC81C, 1)) == b"*\x04\x33" + struct.pack("<f", 1.0)
        # an echo ('0', Gen A only) of two addresses: each with its value, big endian
        echo = ask(sim, bytes.fromhex("2a 0b 30 00 00 c8 16 00 00 c8 18"))
        assert echo == bytes.fromhex("2a 13 30 0000c816 3fa00000 0000c818 c0200000")
    # the lab prints Kp1 every 250 ms; the write at tick ~150 shows from the print at tick 250
    assert out.transcript.split(b"\n\r")[:3] == [b"Kp1 12.50 simu 0 0", b"Kp1 40.00 simu 0 0",
                                                  b"Kp1 -2.50 simu 0 0"]


def test_gen_b_reads_run_into_the_next_variables_and_its_ring_cuts_long_replies(gen_b_config):
    mem = gen_b_config.build.memory
    with BoardRun(gen_b_config) as sim:
        sim.run(50)
        # four floats from whattoprint on: whattoprint, Kp1, samples (2: the request arrives during
        # tick 50 and is answered after its lab(), which took the second sample), then mode (int -2:
        # 0xfffe in its word) with the empty word after it as the high half
        reply = ask(sim, read_request(mem.find("whattoprint").address, 4))
        assert reply[3:15] == struct.pack("<3f", 1.25, 12.5, 2.0)
        assert reply[15:] == bytes.fromhex("feff0000")
        # a 32-bit write into the int: its low 16 bits, sign-extended by the lab's int
        mode = mem.find("mode").address
        ask(sim, b"*\x0b\x33" + struct.pack(">I", mode) + struct.pack("<I", 0x1F234))
        assert ask(sim, read_request(mode, 1))[3:] == bytes.fromhex("34f20000")
        # Gen B ignores '1' and '0'
        assert ask(sim, bytes.fromhex("2a 0b 31 00 00 d0 02 c0 20 00 00")) == b""
        assert ask(sim, bytes.fromhex("2a 07 30 00 00 d0 00")) == b""
        # 600 floats: the 2000-byte ring, the FIFO and the shift register take 2017 bytes; at
        # 11.52 per ms they take 176 ms to leave
        sim.exchange("SerialC", read_request(mem.find("theta1array").address, 600))
        sim.run(sim.tick + 200)
        long = sim.exchange("SerialC", b"")
        assert len(long.sent) == 2017 and long.tx_dropped == 3 + 4 * 600 - 2017
        assert long.sent[1] == (603 & 0xFF)
        sim.run(sim.tick + 300)  # the lab still runs (only its ring overflowed)
        assert sim.get("Kp1") == 12.5
        lab_mode = sim.get("mode")
    assert lab_mode == 0xF234 - 0x10000  # what the lab itself sees: the 16-bit value, negative


def test_a_length_byte_of_0_wedges_serialc_and_the_bridge_says_so_once(gen_b_config):
    said = []
    bridge = SerialBridge({}, said.append)
    with BoardRun(gen_b_config) as sim:
        sim.run(20)
        assert ask(sim, b"*\x00") == b""
        assert ask(sim, read_request(0xD000, 1)) == b""  # nothing is answered any more
        result = sim.exchange("SerialC", b"")
        bridge._report("SerialC", result.wedged_tick, 0, 0)
        bridge._report("SerialC", result.wedged_tick, 0, 0)
    assert result.wedged_tick == 20
    assert len(said) == 1 and "length byte of 0 or 1 at tick 20" in said[0]


def test_a_host_never_reaches_past_the_object_the_compiler_laid_out():
    """The text says ``samples`` holds 400 floats, the compiler made 4: the host tools go by what
    was compiled, so the array reads as zeros and a write far past its end changes nothing."""
    config = make_config(LABS / "host_size_mismatch.c", "hands_off", startup_delay=False)
    mem = config.build.memory
    samples, guard = mem.find("samples"), mem.find("guard")
    assert samples.count == 400  # the text's reading
    with BoardRun(config) as sim:
        sim.run(10)
        assert ask(sim, write_request(samples.address + 2 * 300, 99.0)) == b""
        reply = ask(sim, read_request(samples.address, 4), ticks=20)
        assert struct.unpack("<4f", reply[3:]) == (0.0, 0.0, 0.0, 0.0)
        assert sim.get("guard") == 7.0  # nothing beside the real array was touched
        assert struct.unpack("<f", ask(sim, read_request(guard.address, 1))[3:]) == (7.0,)
