"""``crslab world``: the built-in worlds, and a copy of one to edit into your bench's own.

``crslab world list`` names them; ``crslab world show contest > bench.toml`` prints one's file
(the world file format: docs/worlds.md), which a wheel's user cannot otherwise reach;
``crslab world check FILE`` reads a world file and says what is wrong with it, or what it holds.
"""

from __future__ import annotations

import argparse
import sys

from crslab.cli import CliError


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``world`` subcommand."""
    p = sub.add_parser("world", help="list, show or check worlds (what the arm can touch)",
                       description="The worlds a run may take (--world): crslab's built-in ones, and your "
                       "bench's own world file (docs/worlds.md). 'crslab world show contest > bench.toml' "
                       "copies the contest's layout to edit: move each fixture where your bench has it, "
                       "then 'crslab contest --lab final.c --world bench.toml'.")
    verbs = p.add_subparsers(dest="verb", metavar="VERB", parser_class=type(p))
    v = verbs.add_parser("list", help="the built-in worlds, one line each",
                         description="The built-in worlds, one line each: the name --world takes and what it "
                         "holds.")
    v.set_defaults(func=run_list)
    v = verbs.add_parser("show", help="print a built-in world's file (to copy and edit)",
                         description="Print a built-in world's file exactly, with its comments (each "
                         "number's source): 'crslab world show contest > bench.toml' gives you a file to "
                         "edit.")
    v.add_argument("name", metavar="NAME", help="a built-in world (see 'crslab world list')")
    v.set_defaults(func=run_show)
    v = verbs.add_parser("check", help="check a world file and say what it holds",
                         description="Read and check a world file as every run does (each value, the "
                         "fixtures against each other, the arm at rest, the points the peg must reach): one "
                         "line naming the file, line and key when something is wrong (exit 2), else what it "
                         "holds.")
    v.add_argument("file", metavar="NAME|FILE", help="a world file (or a built-in world's name)")
    v.set_defaults(func=run_check)
    p.set_defaults(func=lambda args: _missing_verb(p))


def _missing_verb(p: argparse.ArgumentParser) -> int:
    p.print_help(sys.stderr)
    return 2


def run_list(args: argparse.Namespace) -> int:
    """``crslab world list``."""
    from crslab.world import WORLD_NAMES, load_world

    for name in WORLD_NAMES:
        world = load_world(name)
        held = ", ".join(world.fixtures()) or "nothing: free air (the default)"
        print(f"{name:<10} {held}")
    return 0


def run_show(args: argparse.Namespace) -> int:
    """``crslab world show NAME``."""
    from crslab.world import WORLD_NAMES, world_file

    if args.name not in WORLD_NAMES:
        raise CliError(f"no built-in world {args.name!r} (built-ins: {', '.join(WORLD_NAMES)}); "
                       "a world file of your own is already a file to edit")
    sys.stdout.write(world_file(args.name)[0].read_text(encoding="utf-8"))
    return 0


def run_check(args: argparse.Namespace) -> int:
    """``crslab world check FILE``."""
    from crslab.world import WorldError, load_world

    try:
        world = load_world(args.file)
    except WorldError as exc:
        raise CliError(str(exc)) from None
    held = ", ".join(world.fixtures()) or "nothing (free air)"
    print(f"{args.file}: world {world.name!r}: {held}")
    return 0
