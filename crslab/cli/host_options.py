"""The options of ``crslab sim`` that let the course's own host tools talk to the simulated board.

``--serial-dir DIR`` puts the board's three serial ports on pseudo-terminals linked at
``DIR/SerialA`` (Tera Term's text), ``DIR/SerialB`` (the Simulink model's packets) and
``DIR/SerialC`` (the MATLAB scripts' variable reads and writes), with the lab's map beside them;
``--serial-tcp BASEPORT`` listens on localhost ports BASEPORT, +1, +2 for the same three (for a
MATLAB on Windows with crslab under WSL); ``--map FILE`` writes the CCS-style map the scripts
parse. See docs/host-tools.md.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

from crslab.cli import CliError
from crslab.cli.live_options import OptionRun, place_links
from crslab.framework_facts import SERIAL_BAUD
from crslab.host_tools.linker_map import write_map
from crslab.host_tools.ports import HostPort, PortError, PtyPort, TcpPort
from crslab.live.bridge import SerialBridge
from crslab.output_paths import folder, with_parent
from crslab.sinks.serial_pty import PortSink
from crslab.sinks.sink import FanOut
from crslab.worker.config import RunConfig

PORT_ROLES = {"SerialA": "Tera Term", "SerialB": "Simulink", "SerialC": "MATLAB"}
"""The board's three serial ports and the host program of each."""


def add_host_options(p: argparse.ArgumentParser) -> None:
    """Add the host-tool options to ``crslab sim``'s parser."""
    g = p.add_argument_group("the course's host tools (MATLAB scripts, Simulink model, Tera Term)")
    g.add_argument("--serial-dir", type=Path, metavar="DIR",
                   help="put the board's serial ports on pseudo-terminals linked at DIR/SerialA (Tera Term), "
                   "DIR/SerialB (Simulink) and DIR/SerialC (MATLAB), with the lab's map in DIR; point the "
                   "course's scripts at DIR/SerialC instead of COM1")
    g.add_argument("--serial-tcp", type=int, metavar="BASEPORT",
                   help="also listen on localhost TCP ports BASEPORT (SerialA), +1 (SerialB), +2 (SerialC), "
                   "e.g. for MATLAB's tcpclient on Windows with crslab under WSL")
    g.add_argument("--map", type=Path, metavar="FILE",
                   help="write the CCS-style linker map of the lab's variables (what the course's parseMap "
                   "reads) to FILE before the first tick")


def host_tools_asked(args: argparse.Namespace) -> bool:
    """Whether the options ask for any host port."""
    return bool(args.serial_dir or args.serial_tcp is not None)


class HostRun(OptionRun):
    """The host ports and map one ``crslab sim`` run asked for; its control is the bridge."""

    def __init__(self, args: argparse.Namespace, config: RunConfig, status: Callable[[str], None]) -> None:
        super().__init__(args, config, status)
        self.serial_a: PortSink | None = None
        """SerialA on ``DIR/SerialA`` (``--pty-wait`` waits for a terminal there)."""
        self._map_in_dir: Path | None = None
        self._bridge: SerialBridge | None = None
        d = args.serial_dir
        if d is not None:
            if args.pty or args.pty_link:
                raise CliError(f"--serial-dir puts SerialA on {d / 'SerialA'} already; "
                               "drop --pty / --pty-link")
            if d.exists() and not d.is_dir():
                raise CliError(f"--serial-dir {d}: is not a directory")
            place_links("--serial-dir", d, [d / name for name in PORT_ROLES])
        if args.serial_tcp is not None and not 1 <= args.serial_tcp <= 65533:
            raise CliError(f"--serial-tcp {args.serial_tcp}: give a port from 1 to 65533 (it uses three)")
        if args.map is not None and args.map.is_dir():
            raise CliError(f"--map {args.map}: is a directory; give a file name for the map")

    def write_maps(self) -> None:
        """Write the map to ``--map`` and into ``--serial-dir`` (before the first tick)."""
        a = self.args
        build = self.config.build
        text = write_map(build.memory, build.source.name)
        targets = [a.map] if a.map is not None else []
        if a.serial_dir is not None:
            folder(a.serial_dir)
            self._map_in_dir = a.serial_dir / f"{build.source.stem}.map"
            targets.append(self._map_in_dir)
        for path in targets:
            try:
                with_parent(path).write_bytes(text.encode())
            except OSError as exc:
                raise CliError(f"{path}: cannot write the map ({exc.strerror})") from None
        if a.map is not None:
            self.status(f"map of {build.source.name}'s variables in {a.map}")

    def start(self, out: FanOut) -> None:
        """Open the ports (after the worker was forked): SerialA joins ``out`` (which closes it);
        SerialB and SerialC are served by the bridge, one of :attr:`controls`."""
        a = self.args
        self.write_maps()
        if not host_tools_asked(a):
            return
        ports: dict[str, list[HostPort]] = {name: [] for name in PORT_ROLES}
        opened: list[tuple[str, HostPort]] = []
        try:
            if a.serial_dir is not None:
                opened += [(name, PtyPort(a.serial_dir / name)) for name in PORT_ROLES]
            if a.serial_tcp is not None:
                opened += [(name, TcpPort(a.serial_tcp + offset)) for offset, name in enumerate(PORT_ROLES)]
        except PortError as exc:
            for _, port in opened:
                port.close()
            raise CliError(str(exc)) from None
        for name, port in opened:
            ports[name].append(port)
            where = f"{port.path}, linked at {port.link}" if isinstance(port, PtyPort) else port.name
            self.status(f"{name} ({PORT_ROLES[name]}) on {where}")
        if self._map_in_dir is not None:
            self.status(f"map of {self.config.build.source.name}'s variables in {self._map_in_dir}")
        for port in ports["SerialA"]:
            sink = PortSink(port)
            out.add(sink)
            if isinstance(port, PtyPort):
                self.serial_a = sink
        self._bridge = SerialBridge({name: ports[name] for name in ("SerialB", "SerialC")}, self.status)
        self.controls.append(self._bridge)
        self.status(f"the ports run at {SERIAL_BAUD} baud, 8N1; bytes sent while no program has a port open "
                    "are dropped, as on a real line")
        if a.pty_wait and self.serial_a is not None:  # last: once attached, the first tick follows at once
            self.status(f"waiting for a terminal on {a.serial_dir / 'SerialA'} before the first tick "
                        "(Ctrl-C to give up)")
            self.serial_a.wait_attached()

    def close(self) -> None:
        """Close SerialB and SerialC (SerialA closes with the run's sinks) and remove the map
        written into ``--serial-dir``."""
        if self._bridge is not None:
            self._bridge.close()
        if self._map_in_dir is not None:
            self._map_in_dir.unlink(missing_ok=True)
