"""``crslab contest``: run a final-project lab in the contest world as a TA runs it, and print its
scorecard.

Exit status 0 when all four tasks are done, 1 when one is not, 2 on bad input (a lab that does
not compile, a missing file, an unknown world, offsets that rest the arm in a fixture), or
``crslab sim``'s status when the lab itself crashes, hangs, ... (its card up to there printed first).
"""

from __future__ import annotations

import argparse
import json
import shlex
import sys
from pathlib import Path

from crslab.cli import CliError
from crslab.cli.run_options import add_run_options, config_from_args, limits_from_args
from crslab.contest.motion import LONGEST_S, STILL_M, STILL_S
from crslab.contest.offsets import Rest, contest_rest
from crslab.contest.run import CONTEST_SCENARIO, CONTEST_WORLD, contest_config, run_contest
from crslab.contest.scorecard import RunFacts, Scorecard, ScorecardError, score
from crslab.lab.includes import with_own_headers
from crslab.run.board_run import RunError
from crslab.run.budget import budget_line
from crslab.run.status import ExitStatus, RunResult, RunStatus
from crslab.untrusted_text import for_terminal
from crslab.worker.config import RunConfig
from crslab.world import WorldError

DURATION_DEFAULT = (f"until the arm comes to rest after its last motion (still within {1000 * STILL_M:g} mm "
                    f"for {STILL_S:g} s), at most {LONGEST_S:g} s")
OFFSETS_DEFAULT = "the lab's own offset_Enc2_rad and offset_Enc3_rad (a lab is calibrated to its bench)"


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``contest`` subcommand."""
    p = sub.add_parser(
        "contest", help="run a final-project lab in the contest world and print its scorecard",
        description="Run a final-project lab file as fast as possible in a world with the contest's "
        "fixtures (default: the contest world), as a TA runs it: the arm resting where the lab's own "
        "offsets say, nobody touching it, until it comes to rest after its last motion. Then score "
        "the run by the course's rules: the peg in the hole (how deep, how long; where it stopped when "
        "it missed), the obstacle (touched by which part of the arm; passed over or around), the "
        "groove (the share of its path inside, where it left or stuck), the egg (the scale's peak and "
        "the time in the force band, in grams; what broke it), the time from the first motion to the "
        "last task, and how the run went (its resting pose, its end, the safety envelope, the motor "
        "board, lab()'s budget). One line each; --json for one object, -o for a picture. Exit 0 when "
        "all four tasks are done, 1 when one is not, 2 on bad input. How each task is scored: "
        "docs/contest.md.")
    add_run_options(p)
    p.set_defaults(world=CONTEST_WORLD, scenario=CONTEST_SCENARIO)
    for action in p._actions:
        if action.dest == "world":
            action.help = f"the world: a built-in name or a world file (TOML) (default: {CONTEST_WORLD})"
        elif action.dest == "scenario":
            action.help = (f"built-in scenario name or TOML file (default: {CONTEST_SCENARIO}: nobody "
                           "touches the arm)")
        elif action.dest == "duration":
            action.help = ("simulated seconds to run, the 4.1 s start-up included (default: "
                           f"{DURATION_DEFAULT})")
        elif action.dest == "offsets":
            action.help = f"the arm's resting motor angles 2 and 3 in rad (default: {OFFSETS_DEFAULT})"
        elif action.dest == "lab":
            action.required = True
            action.help = "the final-project lab file (.c); 'crslab new final' writes one to start from"
    p.add_argument("--json", action="store_true", help="print the scorecard as one JSON object")
    p.add_argument("-o", "--output", type=Path, metavar="FILE.png",
                   help="also draw the card: the peg's path over the fixtures from above, the egg's force "
                   "against time")
    p.set_defaults(func=run_contest_command)


def read_lab_text(path: Path) -> str:
    """The lab file's text with its own headers' (for its offsets); a missing one is a one-line
    error."""
    if not path.is_file():
        raise CliError(f"{path}: no such lab file")
    try:
        return with_own_headers(path, path.read_text(errors="replace"))
    except OSError as exc:
        raise CliError(f"{path}: cannot read it ({exc.strerror})") from None


def contest_run_config(args: argparse.Namespace, rest: Rest) -> RunConfig:
    """The run options' configuration (the world ``--world`` names read once: a bad one is a
    one-line error) made a contest run resting at ``rest``."""
    config = config_from_args(args, log=True)
    if config.world.is_free_air:
        raise CliError(f"{args.world}: world {config.world.name!r} has no fixtures: the contest needs the "
                       "hole, the obstacle, the groove and the egg (the contest world has them)")
    try:
        return contest_config(config, rest)
    except WorldError as exc:
        raise CliError(f"{config.build.source.name}: {exc}") from None


def facts(result: RunResult, config: RunConfig, rest: Rest) -> RunFacts:
    """What the card needs to know of the run besides its log."""
    return RunFacts(result.status, (result.message or "").splitlines()[0] if result.message else "",
                    result.end_tick, result.stats, rest, config.startup_ticks, config.budget_instructions)


def run_contest_command(args: argparse.Namespace) -> int:
    """``crslab contest``."""
    text = read_lab_text(args.lab)
    rest = contest_rest(text, args.offsets)
    config = contest_run_config(args, rest)
    world = config.world
    try:
        result = run_contest(config, duration_s=args.duration, deadline_s=args.deadline,
                             limits=limits_from_args(args))
    except RunError as exc:
        raise CliError(str(exc), status=exc.status.exit_status) from None
    if result.status is RunStatus.NO_LAB:
        raise CliError(result.message, status=result.exit_status)
    if not result.log:
        raise CliError(f"{args.lab.name}: the run ended before its first tick: "
                       f"{for_terminal(result.message or result.status)}", status=result.exit_status)
    try:
        card = score(result.log, world, facts(result, config, rest))
    except ScorecardError as exc:
        raise CliError(str(exc)) from None
    if args.output is not None:
        draw(args.output, result.log, world, card)
    say(args, card)
    print(f"crslab contest: to watch this run: {watch_command(args, rest, card.ended.end_s)}",
          file=sys.stderr)
    cost = budget_line(result.stats)  # what --budget counted
    if cost is not None:
        print(f"crslab contest: {cost}", file=sys.stderr)
    if not result.ok and result.status is not RunStatus.UNMET:
        print(f"crslab contest: the run ended early: {for_terminal(result.message or result.status)}",
              file=sys.stderr)
        return result.exit_status
    return ExitStatus.OK if card.complete else ExitStatus.MISMATCH


def watch_command(args: argparse.Namespace, rest: Rest, end_s: float) -> str:
    """The ``crslab sim`` command that runs this contest run again, at real time: the same lab,
    world, scenario and plant, the arm resting where the contest rested it (``crslab sim`` rests it
    at crslab's arm's pose unless told) and the run's length.

    >>> ns = argparse.Namespace(lab=Path("my final.c"), world="contest", scenario="hands_off", plant=None,
    ...                         motor_board=None, no_startup_delay=False)
    >>> watch_command(ns, Rest((0.0, -0.4321, 0.2087), "lab"), 22.0)
    "crslab sim --lab 'my final.c' --world contest --offsets -0.4321 0.2087 --duration 22"
    """
    cmd = ["crslab", "sim", "--lab", str(args.lab), "--world", str(args.world)]
    if args.scenario != CONTEST_SCENARIO:
        cmd += ["--scenario", str(args.scenario)]
    if args.plant is not None:
        cmd += ["--plant", str(args.plant)]
    if args.motor_board is not None:
        cmd += ["--motor-board", args.motor_board]
    if args.no_startup_delay:
        cmd.append("--no-startup-delay")
    cmd += ["--offsets", repr(rest.motor_rad[1]), repr(rest.motor_rad[2]), "--duration", f"{end_s:g}"]
    return shlex.join(cmd)


def say(args: argparse.Namespace, card: Scorecard) -> None:
    """The card on stdout: one line per task, or one JSON object."""
    if args.json:
        print(json.dumps(card.as_dict()))
    else:
        for line in card.lines():
            print(for_terminal(line))


def draw(path: Path, log: dict, world: object, card: Scorecard) -> None:
    """The card's picture; a path that cannot be written is a one-line error."""
    from crslab.contest.card_plot import draw_card
    from crslab.output_paths import with_parent

    try:
        draw_card(log, world, card, with_parent(path))
    except OSError as exc:
        raise CliError(f"{path}: cannot write the picture ({exc.strerror})") from None
    except ValueError as exc:   # matplotlib: a suffix it has no format for
        raise CliError(f"{path}: {exc}") from None
    print(f"crslab contest: the card's picture is in {path}", file=sys.stderr)
