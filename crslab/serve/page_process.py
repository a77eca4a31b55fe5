"""One page's session: a process of its own that builds the page's labs, prepares its runs and
checks its golden files.

The server starts it from a single-threaded fork server with crslab already imported (as
``crslab grade`` starts its jobs), so it may fork a check's sandboxed worker safely and run the
sandboxed compiler; a crash in it touches no other session. It speaks to the server over one
pipe: the server's checked messages in (:mod:`crslab.serve.page_messages`), messages for the page out,
each prefixed with one byte saying what the server should note, or a prepared run for a run host
(:mod:`crslab.serve.wire`).

Every run is ``crslab sim``'s, put together by :mod:`crslab.run.assemble`: the same
:func:`~crslab.run.assemble.make_config` here (the lab built in the compile sandbox, once: the build
the page was shown is the one that runs; the scenario loaded and checked against it); then a run
host (:mod:`crslab.serve.run_host`) runs it as an instance of its board worker with the same
:class:`~crslab.run.board_run.BoardRun` steps, its transcript written by the same
:class:`~crslab.sinks.transcript_file.TranscriptSink`, the CSV and the rerun recording by the same
sinks as ``--csv`` and ``--rrd`` (in a recorder process,
:class:`crslab.sinks.rerun_writer.RecorderSink`). Only the chunks are the page's
(:data:`~crslab.run.pacing.PAGE_CHUNKS`), so the bytes are the same at any speed.
"""

from __future__ import annotations

import dataclasses
import os
import pickle
import shutil
import signal
from multiprocessing.connection import Connection
from pathlib import Path

from crslab import os_support
from crslab.contest.motion import LONGEST_S
from crslab.contest.offsets import contest_rest
from crslab.contest.run import CONTEST_SCENARIO, CONTEST_WORLD, contest_config
from crslab.framework_facts import TICKS_PER_S
from crslab.lab.build import LabBuild, LabBuildError, LabForbidden, build_lab
from crslab.lab.firmware import is_zig_prepared, prepare_zig
from crslab.plant.plant_params import PlantParamsError
from crslab.run.assemble import DEFAULT_REST_MOTOR_RAD, make_config
from crslab.run.board_run import Limits, RunError
from crslab.run.status import RunStatus
from crslab.scenario.event import seconds_to_tick
from crslab.scenario.load import ScenarioError
from crslab.serve import wire
from crslab.serve.page_messages import compile_diagnostics, habit_diagnostics
from crslab.serve.page_text import SESSION_SUBFOLDERS, PageText
from crslab.serve.run_host import DOWNLOADS, HostedRun
from crslab.serve.stream import Stopped
from crslab.serve.wire import FORWARD, HOST_RUN, RUN_ENDED
from crslab.sinks.page_stream import message
from crslab.worker.config import RunConfig

BAD_INPUT = "bad-input"
"""An ``ended`` status beside the run statuses: the scenario (or another input) could not be used."""


class PageProgress:
    """A text stream whose every line goes to the page as a ``building`` message (what
    :func:`crslab.lab.zig.prepare` says while it builds zig's C library), without ``crslab: ``."""

    def __init__(self, send) -> None:  # noqa: ANN001 - the session's send(message)
        self._send = send
        self._part = ""

    def write(self, text: str) -> int:
        self._part += text
        *lines, self._part = self._part.split("\n")
        for line in lines:
            if line.strip():
                self._send(message("building", message=line.strip().removeprefix("crslab:").strip() + "…"))
        return len(text)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False


@dataclasses.dataclass(frozen=True)
class SessionLimits:
    """What one run may take: simulated seconds, a check's memory, CPU time and wall time (its lab
    runs in the session's own worker, as fast as it can), printed bytes."""

    max_run_s: float = 600.0
    memory_mb: int | None = 1024
    check_cpu_s: float = 60.0
    """The CPU time a check's worker may use (s): past it, it ends (the kernel's limit)."""
    check_wall_s: float = 120.0
    """The wall time a check may take (s): past it, its run ends where it got to."""
    output_mb: float = 16.0
    sandboxed: bool = True


class Session:
    """The page's session: its folder (lab, scenario and golden files, the last run's outputs)."""

    def __init__(self, conn: Connection, folder: Path, limits: SessionLimits) -> None:
        self.conn = conn
        self.folder = folder
        self.limits = limits
        for sub in SESSION_SUBFOLDERS:
            (folder / sub).mkdir(parents=True, exist_ok=True)
        self.page_text = PageText(folder)

    def send(self, data: bytes, tag: bytes = FORWARD) -> None:
        """A message for the page (``tag``: what the server should note), naming files as the page
        named them and no server path (:mod:`crslab.serve.page_text`)."""
        self.conn.send_bytes(tag + self.page_text.message(data))

    # -- files the page sent ----------------------------------------------------------------
    def _write(self, sub: str, file: dict) -> Path:
        folder = self.folder / sub
        for old in folder.iterdir():  # one file at a time: a lab's folder holds only the lab
            old.unlink()
        path = folder / file["name"]
        path.write_text(file["text"], encoding="utf-8")
        return path

    def _write_lab(self, lab: dict) -> Path:
        """The page's lab written to the session's lab folder; returns its path relative to that
        folder, the process's working directory (:func:`serve_session`): built from there, the
        firmware names no session's folder, so every session running the same text shares one
        build (the compiler's and wasmtime's) instead of compiling it again."""
        path = self._write("lab", lab)
        return path.relative_to(Path.cwd()) if path.parent == Path.cwd() else path

    def build(self, lab: dict, tag: bytes = FORWARD) -> tuple[Path, LabBuild] | None:
        """Compile the page's lab and send ``built`` (tagged ``tag``: :data:`RUN_ENDED` when the
        build was the page's whole request); its path and build when it built. Before the installation's
        first build, zig's C library is built (1 to 2 minutes): its progress goes to the page as
        ``building`` messages."""
        path = self._write_lab(lab)
        try:
            try:
                if not is_zig_prepared():
                    prepare_zig(PageProgress(self.send))
            except (RuntimeError, OSError):
                pass  # build_lab says why, as a LabBuildError
            build = build_lab(path, sandboxed=self.limits.sandboxed)
        except LabBuildError as exc:
            self.send(
                message(
                    "built",
                    ok=False,
                    message=str(exc),
                    forbidden=isinstance(exc, LabForbidden),
                    diagnostics=compile_diagnostics(exc.diagnostics, path.name),
                    compiler_output=exc.diagnostics[-20_000:],
                ),
                tag,
            )
            return None
        watched = [{"name": v.name, "ctype": v.ctype, "length": v.length} for v in build.watched]
        self.send(
            message(
                "built",
                ok=True,
                message=f"{path.name} compiled",
                diagnostics=habit_diagnostics(build.habits, path.name),  # the C89 habits, as warnings
                watched=watched,
                generation=build.generation.name,
            ),
            tag,
        )
        return path, build

    def _ended(self, status: RunStatus, message_text: str) -> None:
        self.send(wire.ended(status, message_text), RUN_ENDED)

    # -- a run ------------------------------------------------------------------------------
    def run(self, msg: dict) -> None:
        """Build and run the page's lab, streaming it; ``ended`` comes last, whatever happens."""
        for kind in DOWNLOADS.values():
            (self.folder / "out" / kind).unlink(missing_ok=True)
        built = self.build(msg["lab"])
        if built is None:
            self._ended(RunStatus.BUILD_ERROR, f"{msg['lab']['name']} does not compile: see the marked lines")
            return
        path, build = built
        scenario = msg["scenario"]
        scenario_arg = (
            scenario["name"] if "name" in scenario else str(self._write("scenario", scenario["file"]))
        )
        rest = (DEFAULT_REST_MOTOR_RAD[0], *msg["offsets"]) if msg["offsets"] else None
        contest = contest_rest(msg["lab"]["text"], msg["offsets"]) if msg["contest"] else None
        world = msg["world"]
        if contest is not None:  # as crslab contest runs it: hands off, resting where the lab says
            scenario_arg, rest = CONTEST_SCENARIO, contest.motor_rad
            world = CONTEST_WORLD if world == "none" else world
        record = msg["record"]
        try:
            config = make_config(
                path,
                scenario_arg,
                startup_delay=not msg["no_startup_delay"],
                rest_motor_rad=rest,
                log=True,
                sandbox=self.limits.sandboxed,
                world=world,
                build=build,
            )
            if contest is not None:
                config = contest_config(config, contest)
        except (LabBuildError, ScenarioError, PlantParamsError, ValueError) as exc:
            # what crslab sim turns into one line and exit status 2 (bad input): nothing ran
            line = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            ended = message("ended", status=BAD_INPUT, exit_status=2, bad_input=True, message=line)
            self.send(ended, RUN_ENDED)
            return
        end_tick = seconds_to_tick(msg["duration"]) if msg["duration"] else config.scenario.end_tick
        until_still = contest is not None and not msg["duration"]
        if until_still:
            end_tick = seconds_to_tick(LONGEST_S)
        notes = []
        if end_tick > seconds_to_tick(self.limits.max_run_s):
            end_tick = seconds_to_tick(self.limits.max_run_s)
            notes.append(f"this server runs a lab for at most {self.limits.max_run_s:g} s of simulated time")
        compile_module(config)
        self.hand_over(HostedRun(config, end_tick, msg["speed"], msg.get("phase", 0.0), tuple(notes),
                                 self.folder.resolve(), record_csv=record["csv"], record_rrd=record["rrd"],
                                 output_bytes=int(self.limits.output_mb * 1e6), contest=contest,
                                 until_still=until_still))

    def hand_over(self, run: HostedRun) -> None:
        """The prepared run, for the server to hand to a run host (:mod:`crslab.serve.run_host`),
        which opens it, streams it to the page and says ``ended``."""
        self.conn.send_bytes(HOST_RUN + pickle.dumps(run))

    # -- check against a golden file --------------------------------------------------------
    def check(self, msg: dict) -> None:
        """Run the page's lab as ``crslab check`` does and send ``checked``."""
        from crslab.regress.compare import compare
        from crslab.regress.transcript import GoldenError, read_golden, recorded_run, split_lines
        from crslab.run.assemble import run_kept
        from crslab.world import WORLD_NAMES

        lab = self._write_lab(msg["lab"])
        golden_path = self._write("golden", msg["golden"])
        try:
            golden = read_golden(golden_path)
            self._check_scenario(golden.header.get("scenario"), golden_path.name)
            run = recorded_run(golden, [self.folder / "scenario"])
            if run.plant is not None:
                raise GoldenError(
                    f"{golden_path.name} was recorded with plant file {run.plant}, which the "
                    "page cannot send; check it with crslab check"
                )
            if run.world is not None and run.world not in WORLD_NAMES:
                raise GoldenError(
                    f"{golden_path.name} was recorded in world file {run.world}, which the page cannot "
                    "send; check it with crslab check"
                )
            config = make_config(
                lab,
                run.scenario,
                startup_delay=run.startup_delay is not False,
                rest_motor_rad=run.rest_motor_rad,
                motor_board=run.motor_board,
                sandbox=self.limits.sandboxed,
                world=run.world,
            )
            end_tick = seconds_to_tick(run.duration_s) if run.duration_s else config.scenario.end_tick
            end_tick = min(end_tick, seconds_to_tick(self.limits.max_run_s))
            limits = Limits(memory_mb=self.limits.memory_mb, cpu_s=self.limits.check_cpu_s)
            result = None
            with WallLimit(self.limits.check_wall_s) as wall:
                result = run_kept(config, end_tick, limits=limits)
        except (GoldenError, LabBuildError, ScenarioError, ValueError, RunError) as exc:
            self.send(message("checked", ok=False, report=str(exc)), RUN_ENDED)
            return
        if result is None:  # the time was up before its run began
            self.send(message("checked", ok=False, report=f"the check took more than this server's "
                              f"{self.limits.check_wall_s:g} s"), RUN_ENDED)
            return
        comparison = compare(split_lines(golden.body), split_lines(result.transcript, result.calls))
        report = comparison.report()
        if wall.passed:
            report = (f"the check took more than this server's {self.limits.check_wall_s:g} s: its run was "
                      f"ended at t = {result.end_tick / TICKS_PER_S:.3f} s\n{report}")
        elif not result.ok:
            report = f"{result.diagnosis()}\n{report}"
        self.send(message("checked", ok=comparison.ok and result.ok, report=report), RUN_ENDED)


    def _check_scenario(self, named: str | None, golden: str) -> None:
        """Whether the page may run the scenario a golden file's header names: a built-in one or
        the one uploaded into this session (by its file name); anything else (a server path) is
        refused with one line that says nothing of what is there (raises ``GoldenError``)."""
        from crslab.regress.transcript import GoldenError
        from crslab.scenario.load import builtin_names

        if not named or named in builtin_names():
            return
        uploaded = self.folder / "scenario"
        if "/" not in named and named not in (".", "..") and (uploaded / named).is_file():
            return
        raise GoldenError(
            f"{golden}: its scenario is neither a built-in scenario nor the scenario file uploaded into "
            "this page (Run with it first); the page runs no other"
        )


class WallLimit:
    """``with WallLimit(s) as wall:`` a run in the block that takes longer than ``s`` of wall time
    is ended where it got to (SIGALRM raises ``KeyboardInterrupt`` in this process's main thread,
    which a run ends on as on a Ctrl-C); ``wall.passed`` says whether it was. The session process
    is single-threaded: nothing else uses its alarm."""

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds
        self.passed = False
        self._old: object = None

    def _alarm(self, signum: int, frame: object) -> None:
        self.passed = True
        raise KeyboardInterrupt

    def __enter__(self) -> WallLimit:
        self._old = signal.signal(signal.SIGALRM, self._alarm)
        signal.setitimer(signal.ITIMER_REAL, self.seconds)
        return self

    def __exit__(self, *exc: object) -> bool:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, self._old)  # type: ignore[arg-type]
        return exc[0] is KeyboardInterrupt and self.passed  # it came between the run and here


def compile_module(config: RunConfig) -> None:
    """Have wasmtime compile the run's firmware into the build cache now, unless it is there
    already (a lab's first run): here, in this session's own process, the 0.1 s it takes costs the
    run host's other runs nothing; the host's worker then only loads it."""
    from crslab.worker.wasm_runtime import NotCompiled, WasmImage, compile_kept

    if config.build.native:
        return
    try:
        image = WasmImage.read(config.build.image)
    except OSError:
        return  # a firmware whose seal does not hold: the run host opens it and says why
    kept = image.compiled_path()
    if kept is None:
        return  # no cache to keep it in: the worker compiles it
    try:
        compile_kept(image, kept)
    except (NotCompiled, OSError):
        pass  # the run host's worker compiles it and says why it cannot


def _terminated(signum: int, frame: object) -> None:
    """SIGTERM (the server closing the session: the page went): unwind whatever runs, so a build's
    compiler group and a run's worker are ended on the way out."""
    raise SystemExit(0)


def serve_session(conn: Connection, folder: str, limits: SessionLimits) -> None:
    """The session process's body: carry out the server's messages until it closes the pipe."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the server's to handle
    signal.signal(signal.SIGTERM, _terminated)
    os_support.die_with_parent()
    session = Session(conn, Path(folder), limits)
    os.chdir(session.folder / "lab")  # the page's lab is built by its name alone (Session._write_lab)
    try:
        while True:
            try:
                msg = conn.recv()
            except (EOFError, OSError):
                break
            kind = msg["type"]
            try:
                if kind == "build":
                    session.build(msg["lab"], RUN_ENDED)
                elif kind == "run":
                    session.run(msg)
                elif kind == "check":
                    session.check(msg)
                elif kind in ("stop", "speed", "hand", "release"):
                    pass  # nothing runs: nothing to stop, pace or push
                elif kind == "vars":
                    session.send(
                        message("vars", ok=False, cmd=msg["cmd"], reply="no run is going on: Run first")
                    )
            except Stopped:  # a stop that arrived between two chunks of nothing
                pass
            except (BrokenPipeError, EOFError):
                break
            except Exception as exc:  # noqa: BLE001 - a crslab bug: one line for the page, the session goes on
                import traceback

                traceback.print_exc()
                text = f"crslab failed: {type(exc).__name__}: {exc}"
                if kind in ("run", "check"):
                    session.send(wire.ended(RunStatus.CRASHED, text), RUN_ENDED)
                elif kind == "build":
                    session.send(message("built", ok=False, message=text, diagnostics=[]), RUN_ENDED)
                else:
                    session.send(message("error", message=text))
    finally:
        try:
            signal.signal(signal.SIGTERM, signal.SIG_IGN)  # the server's SIGTERM may come now: finish
        except (OSError, SystemExit):
            pass  # one already pending: CPython says "Signal 15 ignored due to race condition" (or runs it)
        shutil.rmtree(folder, ignore_errors=True)
        os._exit(0)
