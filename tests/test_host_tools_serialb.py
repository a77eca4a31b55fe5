"""SerialB, the course's Simulink link: a host sends FF 7F and seven int16 values every 5 ms; the
board answers at once with int32(10000 * Simulink_PlotVarN) and stores the values into
SIMU_Var1..7_fromSIMU_16bit (docs/host-tools.md, "SerialB: the Simulink packets").

In process, a Python host hands a packet to the board every 5 ticks, exactly as the bridge does
between chunks, so every tick is known: the packet's sync arrives during its tick, the reply holds
the PlotVars after that tick's lab() (the lab sets PlotVar1 = mycount * 0.001 s), and the values
arrive 1.39 ms later, so lab() sees them two ticks after the packet. End to end, ``crslab serial
scope`` is that host on the pseudo-terminal of a running ``crslab sim --serial-dir``."""

import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
from waiting import LineWatcher, wait_exit

from crslab.host_tools.serial_protocols import plot_values, simulink_packet
from crslab.run.api import make_config
from crslab.run.board_run import BoardRun
from crslab.sinks.memory import MemorySink

ROOT = Path(__file__).resolve().parents[1]
GEN_B_LAB = ROOT / "tests" / "labs" / "host_tools_gen_b.c"


def sent_as(value: float) -> int:
    """int32(10000 * value) in single precision, truncated (the board's C, computed here again)."""
    return int(np.trunc(np.float32(10000) * np.float32(value)))


def test_a_simulink_host_every_5_ms_gets_each_answer_and_its_values_reach_the_lab():
    config = make_config(GEN_B_LAB, "hands_off", startup_delay=False)
    replies, out = [], MemorySink()
    with BoardRun(config) as sim:
        for k in range(120):  # a packet at ticks 0, 5, ..., 595 carrying V1 = k, V2 = -k
            assert sim.exchange("SerialB", simulink_packet([k, -k, 0, 0, 0, 0, 0])).taken == 16
            sim.run(sim.tick + 5, out)
            replies.append(sim.exchange("SerialB", b"").sent)
    # right after reset the first byte is tested for 7F alone: the first packet is not answered
    assert replies[0] == b""
    for k in range(1, 120):
        assert len(replies[k]) == 16, k  # one reply per packet, within the 5 ms
        plots = plot_values(replies[k])
        tick = 5 * k  # the sync arrived during this tick: the PlotVars after its lab()
        # the lab computes mycount * 0.001 in double, a float on the board, and stores it
        assert plots[0] == sent_as(np.float32(tick) * np.float32(0.001)) / 10000, k
        assert plots[1] == sent_as(12.5) / 10000 and plots[3] == sent_as(-2.0 / 3.0) / 10000
        # PlotVar3 is SIMU_Var1 as lab() saw it: packet k's values are stored after tick 5k + 1's
        # lab(), so lab() of tick 5k still shows packet k - 1's (and nothing before packet 1's)
        assert plots[2] == (k - 1 if k >= 2 else 0), k
    # the lab prints SIMU_Var1 and SIMU_Var2 every 250 ms: at tick 500, packet 99's (sent at 495)
    assert out.transcript.split(b"\n\r")[2] == b"Kp1 12.50 simu 99 -99 mode -2"


def test_crslab_serial_scope_is_that_host_on_a_running_sim(tmp_path):
    ports = tmp_path / "ports"
    cmd = [sys.executable, "-m", "crslab", "sim", "--lab", str(GEN_B_LAB), "--scenario", "hands_off",
           "--no-startup-delay", "--serial-dir", str(ports), "--duration", "600", "--no-stdin", "--quiet"]
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    sim = subprocess.Popen(cmd, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        err = LineWatcher(sim.stderr, "crslab sim's stderr")
        out = LineWatcher(sim.stdout, "crslab sim's stdout")
        err.wait_for("SerialC .* linked at")
        scope = subprocess.run([sys.executable, "-m", "crslab", "serial", "scope", "--dir", str(ports),
                                "--print", "--count", "60", "--simu", "7", "-3", "0", "0", "0", "0", "0"],
                               cwd=ROOT, capture_output=True, text=True, timeout=120)
        assert scope.returncode == 0, scope.stderr
        rows = [[float(x) for x in line.split()] for line in scope.stdout.splitlines()]
        assert len(rows) == 60 and "60 replies" in scope.stderr
        times = [r[1] for r in rows]  # PlotVar1: the simulated time of lab() when each packet arrived
        assert all(b > a for a, b in zip(times, times[1:]))
        assert {r[2] for r in rows} == {12.5} and {r[4] for r in rows} == {-0.6666}
        assert rows[-1][3] == 7.0  # PlotVar3 = SIMU_Var1: the value sent reached the lab
        rrd = tmp_path / "scope.rrd"  # the same as a rerun recording
        simu = ["--simu", "7", "-3", "0", "0", "0", "0", "0"]
        saved = subprocess.run([sys.executable, "-m", "crslab", "serial", "scope", "--dir", str(ports),
                                "--rrd", str(rrd), "--count", "20", *simu],
                               cwd=ROOT, capture_output=True, text=True, timeout=120)
        assert saved.returncode == 0 and "20 replies" in saved.stderr, saved.stderr
        assert rrd.stat().st_size > 1000
        # MATLAB's side on the same run: write Kp1, read it back; the lab prints both
        w = subprocess.run([sys.executable, "-m", "crslab", "serial", "write", "Kp1", "40", "--dir",
                            str(ports)], cwd=ROOT, capture_output=True, text=True, timeout=120)
        assert w.returncode == 0 and w.stdout.startswith("Kp1 = 40   (read back at 0000d002)"), w.stderr
        out.wait_for(r"^Kp1 40\.00 simu 7 -3 mode -2")
        sim.send_signal(signal.SIGINT)
        assert wait_exit(sim, "Ctrl-C (SIGINT)") == 130
    finally:
        sim.kill()
    assert not any(os.path.lexists(ports / name) for name in ("SerialA", "SerialB", "SerialC"))
