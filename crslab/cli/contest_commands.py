"""``crslab contest``: run a final-project lab in the contest world and print its scorecard.

Exit status 0 when all four tasks are done, 1 when one is not, 2 on bad input (a lab that does
not compile, a missing file, an unknown world), or ``crslab sim``'s status when the lab itself
crashes, hangs, ...
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path

from crslab.cli import CliError
from crslab.cli.run_options import add_run_options, config_from_args, run_to_end
from crslab.contest.scorecard import Scorecard, ScorecardError, score
from crslab.run.budget import budget_line
from crslab.run.status import ExitStatus, RunStatus
from crslab.scenario.event import seconds_to_tick
from crslab.untrusted_text import for_terminal
from crslab.worker.config import RunConfig
from crslab.world.layout import World, WorldError, load_world

CONTEST_WORLD = "contest"
CONTEST_SCENARIO = "hands_off"
"""Nobody touches the arm during a contest run."""
CONTEST_DURATION_S = 30.0
"""Simulated seconds of a contest run (the 4.1 s start-up included) unless ``--duration``."""


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``contest`` subcommand."""
    p = sub.add_parser(
        "contest", help="run a final-project lab in the contest world and print its scorecard",
        description="Run a final-project lab file as fast as possible in a world with the contest's "
        "fixtures (default: the contest world) and score the run: the peg's depth in the hole and for "
        "how long, the obstacle touched or not, the groove (the share of its path inside, the largest "
        "side force, where it left), the egg (the scale's peak and the time in the force band, in "
        "grams; broken or not), and the time from the first motion to the last task. One line per "
        "task with its evidence; --json for one object, -o for a picture. Exit 0 when all four tasks "
        "are done, 1 when one is not, 2 on bad input. How each task is scored: docs/contest.md.")
    add_run_options(p)
    if not any(a.dest == "world" for a in p._actions):
        p.add_argument("--world", metavar="NAME|FILE", help="the world: a built-in name or a layout file")
    p.set_defaults(world=CONTEST_WORLD, scenario=CONTEST_SCENARIO)
    for action in p._actions:
        if action.dest == "world":
            action.help = f"the world: a built-in name or a layout file (TOML) (default: {CONTEST_WORLD})"
        elif action.dest == "scenario":
            action.help = (f"built-in scenario name or TOML file (default: {CONTEST_SCENARIO}: nobody "
                           "touches "
                           "the arm)")
        elif action.dest == "duration":
            action.help = f"simulated seconds to run (default: {CONTEST_DURATION_S:g}, start-up included)"
        elif action.dest == "lab":
            action.required = True
            action.help = "the final-project lab file (.c); 'crslab new final' writes one to start from"
    p.add_argument("--json", action="store_true", help="print the scorecard as one JSON object")
    p.add_argument("-o", "--output", type=Path, metavar="FILE.png",
                   help="also draw the card: the peg's path over the fixtures from above, the egg's force "
                   "against time")
    p.set_defaults(func=run_contest)


def load_contest_world(name: str) -> World:
    """The world named or found at ``name``; a bad one is a one-line error."""
    try:
        return load_world(name)
    except WorldError as exc:
        raise CliError(str(exc)) from None
    except OSError as exc:
        raise CliError(f"{name}: cannot read the world file ({exc.strerror})") from None


def contest_config(args: argparse.Namespace, world: World) -> RunConfig:
    """The run options' configuration, logging the scope rows, in ``world``."""
    return dataclasses.replace(config_from_args(args, log=True), world=world)


def run_contest(args: argparse.Namespace) -> int:
    """``crslab contest``."""
    if not args.lab.is_file():
        raise CliError(f"{args.lab}: no such lab file")
    world = load_contest_world(args.world)
    config = contest_config(args, world)
    end_tick = seconds_to_tick(args.duration or CONTEST_DURATION_S)
    result = run_to_end(config, end_tick, args)
    if not result.log:
        raise CliError(f"{args.lab.name}: the run ended before its first tick: "
                       f"{for_terminal(result.message or result.status)}", status=result.exit_status)
    try:
        card = score(result.log, world)
    except ScorecardError as exc:
        raise CliError(str(exc)) from None
    if args.output is not None:
        draw(args.output, result.log, world, card)
    say(args, card)
    cost = budget_line(result.stats)  # what --budget counted
    if cost is not None:
        print(f"crslab contest: {cost}", file=sys.stderr)
    if not result.ok and result.status is not RunStatus.UNMET:
        print(f"crslab contest: the run ended early: {for_terminal(result.message or result.status)}",
              file=sys.stderr)
        return result.exit_status
    return ExitStatus.OK if card.done == 4 else ExitStatus.MISMATCH


def say(args: argparse.Namespace, card: Scorecard) -> None:
    """The card on stdout: one line per task, or one JSON object."""
    if args.json:
        print(json.dumps(card.as_dict()))
    else:
        for line in card.lines():
            print(line)


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
