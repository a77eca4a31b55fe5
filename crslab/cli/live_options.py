"""The options of ``crslab sim`` and ``crslab debug`` that open windows into the running lab.

``--rerun`` / ``--rrd FILE`` (rerun scopes and 3D), ``--pty`` / ``--pty-link PATH`` /
``--pty-wait`` (the serial line on a pseudo-terminal), ``--viewer`` (MuJoCo's viewer), and the
live-variable commands read from standard input while the run goes on. The file outputs
(``--transcript``, ``--csv``) are :mod:`crslab.cli.sink_options`'.

:class:`LiveRun` checks the options before the worker starts (bad paths are one-line errors)
and opens ``--rrd``'s recording in the writer process the command forked at its start (see
:mod:`crslab.sinks.rerun_writer`); it starts everything that spawns threads or windows only
after the worker was forked (:meth:`LiveRun.start`): the sinks join the run's fan-out, and the
typed commands and the viewer are the run's :attr:`LiveRun.controls`, served between chunks of
ticks.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from crslab.cli import CliError
from crslab.cli.sink_options import writable
from crslab.framework_facts import SERIAL_BAUD
from crslab.live.console import VarConsole
from crslab.output_paths import folder
from crslab.run.running import LiveControl
from crslab.scopes.display import missing_display
from crslab.sinks.rerun_writer import WriterSink, discard_writer, take_writer
from crslab.sinks.sink import FanOut
from crslab.sinks.threaded import ThreadedSink
from crslab.worker.config import RunConfig


def add_live_options(p: argparse.ArgumentParser) -> None:
    """Add the scope, terminal and viewer options to a run command's parser."""
    g = p.add_argument_group("scopes and live windows")
    g.add_argument("--rerun", action="store_true",
                   help="open the rerun viewer on the run: Simulink_PlotVar1..4, motor angles, torques, "
                   "safety flag, LEDs, serial lines and the arm in 3D")
    g.add_argument("--rrd", type=Path, metavar="FILE",
                   help="save the same rerun recording to FILE (headless)")
    g.add_argument("--pty", action="store_true",
                   help="also send the serial output to a pseudo-terminal (its path is printed on stderr) "
                   "for miniterm, picocom or screen; bytes sent while no terminal is attached are dropped")
    g.add_argument("--pty-link", type=Path, metavar="PATH",
                   help="keep a symlink at PATH to the pseudo-terminal (implies --pty)")
    g.add_argument("--pty-wait", action="store_true",
                   help="start the run only once a terminal has opened the pseudo-terminal, so it misses "
                   "nothing printed (implies --pty)")
    g.add_argument("--viewer", action="store_true",
                   help="open MuJoCo's viewer on the arm (Ctrl + right-drag on a link pushes it)")
    g.add_argument("--no-stdin", action="store_true",
                   help="do not read live-variable commands (get, set, list) from standard input")


def live_needs_log(args: argparse.Namespace) -> bool:
    """Whether the options ask for the run's scope signals (rerun, the viewer's pose)."""
    return bool(args.rerun or args.rrd or args.viewer)


def stdin_commands_possible() -> bool:
    """True when standard input can carry commands without stopping a background job."""
    stream = sys.stdin
    if stream is None or stream.closed:
        return False
    try:
        fd = stream.fileno()
        if os.isatty(fd) and os.tcgetpgrp(fd) != os.getpgrp():
            return False  # a background job reading its terminal would be stopped (SIGTTIN)
    except (OSError, ValueError):
        return False
    return True


def place_links(option: str, value: Path, links: Sequence[Path]) -> None:
    """Make the folder of the symlinks ``links`` that ``option value`` asks for (``value`` is the
    one link, or the folder of several) and check that none would replace what is not a symlink
    (a port replaces only a symlink of its own); a failure is one line naming the option.

    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp()); (d / "SerialA").write_text("a file")
    6
    >>> place_links("--serial-dir", d, [d / "SerialA"])
    Traceback (most recent call last):
    crslab.cli.CliError: --serial-dir ...: .../SerialA exists and is not a symlink; not replacing it
    >>> place_links("--pty-link", d / "new" / "pty", [d / "new" / "pty"]); (d / "new").is_dir()
    True
    """
    for link in links:
        if link.exists() and not link.is_symlink():
            named = "" if link == value else f"{link} "
            raise CliError(f"{option} {value}: {named}exists and is not a symlink; not replacing it")
    place, which = (value.parent, "its folder") if value in links else (value, "this folder")
    try:
        folder(place)
    except OSError as exc:
        raise CliError(f"{option} {value}: cannot make {which} ({exc.strerror})") from None


class OptionRun:
    """What one run's options ask for beyond its sinks (:class:`LiveRun`,
    :class:`crslab.cli.host_options.HostRun`): ``status`` says one line on stderr (with the
    command's prefix); :attr:`controls` are served between chunks of ticks once started."""

    def __init__(self, args: argparse.Namespace, config: RunConfig, status: Callable[[str], None]) -> None:
        self.args = args
        self.config = config
        self.status = status
        self.controls: list[LiveControl] = []


class LiveRun(OptionRun):
    """The live windows one ``crslab sim`` or ``crslab debug`` run asked for; its controls are the
    typed commands and the viewer."""

    def __init__(self, args: argparse.Namespace, config: RunConfig, status: Callable[[str], None]) -> None:
        super().__init__(args, config, status)
        if args.rrd is not None:
            writable(args.rrd, "the rerun recording")
        if args.pty_link is not None:
            place_links("--pty-link", args.pty_link, [args.pty_link])
        self._rrd_writer: WriterSink | None = None
        """--rrd's sink when the writer process forked at the command's start writes it: opened
        now, so that the recording is set up before the first tick."""
        writer = take_writer() if args.rrd and not self._spawn_viewer() else None
        discard_writer()  # forked for --rrd but not needed: the viewer keeps rerun in-process
        if writer is not None:
            self._rrd_writer = WriterSink(writer, rrd_path=args.rrd, name=config.build.source.name,
                                          on_status=self.status, world=config.world)

    def _spawn_viewer(self) -> bool:
        return bool(self.args.rerun) and not missing_display()

    def worker_started(self) -> None:
        """The worker was forked: start what is slow to start (rerun's import, not needed when the
        ``--rrd`` writer process does it) so that it overlaps the worker's start-up."""
        if self._spawn_viewer() or (self.args.rrd and self._rrd_writer is None):
            from crslab.sinks.rerun_scopes import preload

            preload()

    def start(self, out: FanOut) -> None:
        """Open everything (after the worker was forked): the sinks join ``out``, which closes them."""
        a = self.args
        pty = None
        if a.pty or a.pty_link or (a.pty_wait and not getattr(a, "serial_dir", None)):  # or --serial-dir
            from crslab.sinks.serial_pty import PtyError, PtySink

            try:
                pty = PtySink(a.pty_link)
            except PtyError as exc:
                raise CliError(str(exc)) from None
            where = f" (linked at {pty.link})" if pty.link else ""
            self.status(f"serial port on {pty.path}{where}: attach a terminal, "
                        f"e.g. python -m serial.tools.miniterm {pty.link or pty.path} {SERIAL_BAUD}")
            out.add(pty)
        spawn = a.rerun
        if spawn and missing_display():
            self.status(f"--rerun: {missing_display()}; running without the rerun viewer"
                        + ("" if a.rrd else " (--rrd FILE saves a recording to open later)"))
            spawn = False
        if self._rrd_writer is not None:
            out.add(self._rrd_writer)
        elif spawn or a.rrd:
            from crslab.sinks.rerun_scopes import RerunSink

            rerun_sink = RerunSink(rrd_path=a.rrd, spawn=spawn, name=self.config.build.source.name,
                                   on_status=self.status, world=self.config.world)
            rerun_sink.prepare()
            out.add(ThreadedSink(rerun_sink))
        if a.viewer:
            from crslab import crs
            from crslab.live.viewer import MujocoViewer

            viewer = MujocoViewer(crs.motor_to_dh(self.config.rest_motor_rad), on_status=self.status,
                                  world=self.config.world)
            if viewer.start():
                out.add(viewer)
                self.controls.append(viewer)
        if not a.no_stdin and stdin_commands_possible():
            console = VarConsole(self.config.build.watched)
            console.start()
            self.controls.insert(0, console)
        if pty is not None and a.pty_wait:  # last: once attached, the first tick follows at once
            self.status(f"waiting for a terminal on {pty.link or pty.path} before the first tick "
                        "(Ctrl-C to give up)")
            pty.wait_attached()
