"""``crslab sim``'s host ports from the outside: host programs attached to SerialB and SerialC that
only read change nothing the lab prints (the transcript equals a run without them); the same ports
over TCP (``--serial-tcp``); bad options are one line each."""

import os
import signal
import socket
import subprocess
import sys
import threading
from pathlib import Path

import serial
from waiting import GUARD_S, LineWatcher, join, wait_exit

from crslab.host_tools.serial_protocols import plot_values, read_request, simulink_packet
from crslab.lab.build import text_memory

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_LAB = ROOT / "csrc" / "labs" / "lab1_kinematics.c"
GEN_A_LAB = ROOT / "tests" / "labs" / "host_tools_gen_a.c"
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}


def crslab(*args, **kw):
    return subprocess.Popen([sys.executable, "-m", "crslab", *args], cwd=ROOT, env=ENV, text=True, **kw)


class Host(threading.Thread):
    """A host program that keeps asking until the port goes away: MATLAB reads of theta1array (100
    floats) on SerialC, or Simulink packets of zeros on SerialB, each sent once the last answer
    arrived (the board drops the first packet after reset: Simulink's second one starts it)."""

    def __init__(self, path: Path, kind: str) -> None:
        super().__init__(name=f"host on {path.name}", daemon=True)
        self.path, self.kind = path, kind
        self.answers: list[bytes] = []
        self.error: BaseException | None = None

    def run(self) -> None:
        if self.kind == "tera term":  # SerialA: everything until the port closes
            with serial.Serial(str(self.path), 115200, timeout=GUARD_S) as port:
                while True:
                    try:
                        chunk = port.read(max(1, port.in_waiting))
                    except serial.SerialException:
                        return
                    if not chunk:
                        self.error = AssertionError(f"nothing on SerialA for {GUARD_S:g} s")
                        return
                    self.answers.append(chunk)
        address = text_memory(DEFAULT_LAB.read_text(), "lab1").find("theta1array").address
        request, size = ((read_request(address, 100), 403) if self.kind == "matlab"
                         else (simulink_packet([0] * 7), 16))
        try:
            with serial.Serial(str(self.path), 115200, timeout=GUARD_S) as port:
                if self.kind == "simulink":
                    port.write(request)
                while True:
                    port.write(request)
                    answer = port.read(size)
                    if len(answer) < size:
                        raise AssertionError(f"{self.kind}: {len(answer)} of {size} bytes came back")
                    self.answers.append(answer)
        except serial.SerialException:  # crslab closed the port: the run ended
            pass
        except BaseException as exc:  # noqa: BLE001 - reported by the test
            self.error = exc


def test_hosts_that_only_read_leave_the_transcript_unchanged(tmp_path):
    ports, with_hosts, alone = tmp_path / "ports", tmp_path / "with.bin", tmp_path / "alone.bin"
    sim = crslab("sim", "--speed", "4", "--duration", "6.2", "--serial-dir", str(ports), "--pty-wait",
                 "--transcript", str(with_hosts), "--no-stdin", "--quiet", stdout=subprocess.DEVNULL,
                 stderr=subprocess.PIPE)
    try:
        err = LineWatcher(sim.stderr, "crslab sim's stderr")
        err.wait_for(f"waiting for a terminal on {ports / 'SerialA'}")  # --pty-wait: on SerialA
        hosts = [Host(ports / "SerialC", "matlab"), Host(ports / "SerialB", "simulink")]
        for h in hosts:
            h.start()
        tera_term = Host(ports / "SerialA", "tera term")  # the run starts once it opened SerialA
        tera_term.start()
        assert wait_exit(sim, "the end of a 6.2 s run") == 0, err.all()
        for h in [*hosts, tera_term]:
            join(h, f"{h.name} (it ends when crslab closes the port)")
            assert h.error is None, h.error
    finally:
        sim.kill()
    matlab, simulink = (h.answers for h in hosts)
    assert len(matlab) > 20 and len(simulink) > 100  # they kept asking through the run
    assert all(a[:3] == b"*\x67\x33" for a in matlab)  # 100 floats: (3 + 100) & 0xff
    # Lab 1 sets PlotVar1..4 to the motor angles and z: 0 until lab() first runs at 4.1 s, then
    # the arm's pose as the tour moves it
    values = [plot_values(a) for a in simulink]
    assert values[0] == (0.0, 0.0, 0.0, 0.0) and len(set(values)) > 10
    r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--duration", "6.2", "--transcript",
                        str(alone), "--no-stdin", "--quiet"], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert with_hosts.read_bytes().count(b"\n\r") == 15 and with_hosts.read_bytes() == alone.read_bytes()
    assert b"".join(tera_term.answers) == alone.read_bytes()  # SerialA is Tera Term's text


def free_base_port() -> int:
    """A localhost port with the two after it free too."""
    for _ in range(50):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            base = s.getsockname()[1]
        if base > 65533:
            continue
        try:
            for offset in range(3):
                with socket.socket() as s:
                    s.bind(("127.0.0.1", base + offset))
        except OSError:
            continue
        return base
    raise AssertionError("no three free localhost ports in a row")


def test_serial_tcp_serves_tera_term_and_matlab_on_localhost():
    base = free_base_port()
    sim = crslab("sim", "--lab", str(GEN_A_LAB), "--scenario", "hands_off", "--no-startup-delay",
                 "--serial-tcp", str(base), "--duration", "600", "--no-stdin", "--quiet",
                 stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        err = LineWatcher(sim.stderr, "crslab sim's stderr")
        out = LineWatcher(sim.stdout, "crslab sim's stdout")
        err.wait_for(f"SerialC \\(MATLAB\\) on TCP 127.0.0.1:{base + 2}")
        with socket.create_connection(("127.0.0.1", base), timeout=GUARD_S) as tera_term:
            text = b""
            while text.count(b"\n\r") < 2:
                text += tera_term.recv(4096)
        assert b"Kp1 12.50 simu 0 0\n\r" in text
        r = subprocess.run([sys.executable, "-m", "crslab", "serial", "write", "Kp1", "-7.25", "--tcp",
                            str(base + 2), "--lab", str(GEN_A_LAB)], cwd=ROOT, capture_output=True, text=True,
                           timeout=120)
        assert r.returncode == 0 and r.stdout.startswith("Kp1 = -7.25   (read back at 0000c818)"), r.stderr
        out.wait_for(r"^Kp1 -7\.25 simu 0 0$")
        sim.send_signal(signal.SIGINT)
        assert wait_exit(sim, "Ctrl-C (SIGINT)") == 130
    finally:
        sim.kill()


def test_bad_host_options_are_one_line(tmp_path):
    a_file = tmp_path / "file"
    a_file.write_text("x")
    taken = socket.create_server(("127.0.0.1", 0))
    try:
        port = taken.getsockname()[1]
        for args, why in [
            (["--serial-dir", str(tmp_path / "p"), "--pty-link", str(tmp_path / "tty")], "drop --pty"),
            (["--serial-dir", str(a_file)], "is not a directory"),
            (["--serial-dir", str(a_file / "such")], "cannot make this folder (Not a directory)"),
            (["--serial-tcp", "70000"], "give a port from 1 to 65533"),
            (["--serial-tcp", str(port)], f"cannot listen on TCP 127.0.0.1:{port}"),
            (["--map", str(tmp_path)], "is a directory"),
        ]:
            r = subprocess.run([sys.executable, "-m", "crslab", "sim", "--fast", "--duration", "0.1",
                                "--quiet", "--no-stdin", *args], cwd=ROOT, capture_output=True, text=True)
            assert r.returncode == 2 and r.stderr.count("\n") == 1 and why in r.stderr, (args, r.stderr)
    finally:
        taken.close()
    r = subprocess.run([sys.executable, "-m", "crslab", "serial", "read", "Kp1"], cwd=ROOT,
                       capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "say where" in r.stderr
