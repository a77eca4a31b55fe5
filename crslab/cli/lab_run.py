"""One ``crslab sim`` or ``crslab debug`` run as its command assembles it: the configuration from
the run options, every output as a sink of one fan-out (the narration on stderr, stdout as Tera
Term shows it, the file outputs of :mod:`crslab.cli.sink_options`, the live windows, SerialA on
the host ports), the live controls, the worker, and what is said once the run has ended: the
end-of-run report is the last sink's (:class:`~crslab.sinks.at_end.AtEnd`), said when the run
ends (``on_end``), after what the sinks before it say then (the waypoint tracking's report, the
C28x check's findings).

The commands differ only in what they pass: ``sim`` its host ports, waypoint tracking and pace,
``debug`` its debugger (the worker's setup, a control, and where chunks end) and introduction.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Callable, Sequence

from crslab.cli import CliError
from crslab.cli.host_options import HostRun
from crslab.cli.live_options import LiveRun, live_needs_log
from crslab.cli.run_options import limits_from_args
from crslab.cli.run_report import print_run_notes, summary, summary_line
from crslab.cli.sink_options import check_sinks, open_sinks, preload_sinks, sinks_need_scope_rows
from crslab.lab.compiler import native_widths_note
from crslab.run.assemble import started
from crslab.run.board_run import BoardRun, RunError
from crslab.run.budget import near_budget_warning
from crslab.run.running import LiveControl, RunDebugger
from crslab.run.status import RunResult
from crslab.scenario.event import seconds_to_tick
from crslab.sinks.at_end import AtEnd
from crslab.sinks.narration import NarrationSink
from crslab.sinks.sink import FanOut, Sink, SinkError
from crslab.sinks.stdout import StdoutSink
from crslab.untrusted_text import for_terminal
from crslab.worker.config import RunConfig
from crslab.worker.debug_setup import DebugSetup


def end_tick_of(args: argparse.Namespace, config: RunConfig) -> int:
    """The tick the run ends at: ``--duration``, else the scenario's end."""
    return seconds_to_tick(args.duration) if args.duration else config.scenario.end_tick


def scope_rows_asked(args: argparse.Namespace) -> bool:
    """Whether an output the options ask for reads the run's scope rows (the run then logs them)."""
    return live_needs_log(args) or sinks_need_scope_rows(args)


class LabRun:
    """The outputs, windows and controls of one run of ``config`` (built from ``args``), said with
    ``crslab COMMAND: `` before each line. Bad options are one-line errors here, before the worker
    starts; :meth:`run` runs it and says how it went (:meth:`report`, when it ends)."""

    def __init__(self, args: argparse.Namespace, config: RunConfig, command: str, *,
                 host_ports: bool = False) -> None:
        self.args = args
        self.config = config
        self.prefix = f"crslab {command}: "
        self.lab_name = config.build.source.name
        self.end_tick = end_tick_of(args, config)
        self.live = LiveRun(args, config, self.say)
        self.host = HostRun(args, config, self.say) if host_ports else None
        check_sinks(args)
        self.stdout = StdoutSink()
        # the narration comes first: an event is said before what the lab printed after it
        self.narration = NarrationSink(config.scenario.events, self.stdout, quiet=args.quiet,
                                       prefix=self.prefix)
        self.out = FanOut([self.narration, self.stdout])
        self.wall_s = 0.0
        self._start = 0.0

    def say(self, line: str) -> None:
        """One line on stderr, now."""
        print(f"{self.prefix}{line}", file=sys.stderr, flush=True)

    def say_build_notes(self) -> None:
        """What the build found that the board does otherwise, one line each (also with --quiet): the
        C89 habits it built, and in a native build where the host's widths and layout differ."""
        build = self.config.build
        for line in build.habits:
            self.say(f"warning: {line}")
        if build.native:
            try:
                self.say(f"note: {native_widths_note(build.source.read_text(errors='replace'))}")
            except OSError:
                pass

    def _worker_started(self) -> None:
        self.live.worker_started()
        preload_sinks(self.args)

    def run(self, introduction: Callable[[int], str], *, speed: float | None,
            extra_sinks: Sequence[Sink] = (), controls: Sequence[LiveControl] = (),
            debug: DebugSetup | None = None, debugger: RunDebugger | None = None,
            prepare: Callable[[BoardRun], None] | None = None,
            ready: Callable[[BoardRun], None] | None = None, lab_cost: bool = True) -> RunResult:
        """Start the worker, open every output, say ``introduction(end_tick)``, run to the end,
        say how it went (:meth:`report`, the last sink's: ``extra_sinks`` say theirs before it) and
        close the outputs (a failure to finish a file is a one-line error). ``prepare(sim)`` comes
        before the introduction (it may move :attr:`end_tick`), ``ready(sim)`` right after it;
        ``controls`` are served before the live windows', and ``debug``, ``debugger`` go to the
        worker and the run (``crslab debug``); ``lab_cost`` goes to :meth:`report`."""
        self._start = time.monotonic()
        try:
            with started(self.config, deadline_s=self.args.deadline, limits=limits_from_args(self.args),
                         debug=debug, on_started=self._worker_started) as sim:
                open_sinks(self.args, self.config, self.out)
                self.live.start(self.out)
                if self.host is not None:
                    self.host.start(self.out)
                for sink in extra_sinks:
                    self.out.add(sink)
                self.out.add(AtEnd(lambda result: self.report(result, lab_cost=lab_cost)))
                if prepare is not None:
                    prepare(sim)
                self.say_build_notes()
                self.narration.say(introduction(self.end_tick))
                self.narration.on_reached(0)
                if ready is not None:
                    ready(sim)
                host_controls = self.host.controls if self.host is not None else []
                result = sim.run(self.end_tick, self.out, speed=speed,
                                 controls=[*controls, *self.live.controls, *host_controls], debugger=debugger)
        except RunError as exc:
            raise CliError(str(exc), status=exc.exit_status) from None
        finally:
            if self.host is not None:
                self.host.close()
            try:
                self.out.close()
            except SinkError as exc:
                raise CliError(str(exc)) from None
        return result

    def report(self, result: RunResult, *, lab_cost: bool = True) -> int:
        """Say how the run went on stderr (its notices, failed expectations, the summary or
        ``--json``, the diagnosis); ``lab_cost`` False leaves lab()'s timings out of the summary
        line (they mean nothing once a debugger held it). Returns the exit status."""
        self.wall_s = time.monotonic() - self._start
        self.stdout.flush()  # the run's last bytes before what is said of it
        print_run_notes(self.prefix, self.lab_name, result, self.config.build.generation)
        info = summary(result, self.wall_s)
        if self.args.json:
            print(json.dumps(info), file=sys.stderr)
        elif lab_cost:
            self.say(summary_line(info))
        else:
            self.say(f"{info['simulated_s']:.3f} s simulated in {self.wall_s:.2f} s")
        warning = near_budget_warning(self.lab_name, info) if lab_cost else None
        if warning:
            self.say(warning)
        if result.message:
            self.say(for_terminal(result.message))
        return result.exit_status
