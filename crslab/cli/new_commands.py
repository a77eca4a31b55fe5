"""``crslab new LAB FILE``: write a starting lab file (crslab/starters) to begin a lab from."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from crslab.cli import CliError
from crslab.generations import GENERATIONS, NEWEST, named
from crslab.output_paths import with_parent
from crslab.starters import LABS, starter_text

RUN_WITH = {"lab4": "crslab sim --lab {path} --scenario lab4_push",
            "final": "crslab contest --lab {path}"}
"""The command each starter is run with when plain ``crslab sim --lab FILE`` is not it: Lab 4 on
the course's push at the end effector, the final project as the contest judges it."""


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``new`` subcommand."""
    names = [g.name for g in GENERATIONS]
    p = sub.add_parser(
        "new",
        help=f"write a starting lab file (lab1..lab4, final; Gen {' or '.join(names)}) to begin a lab from",
        description="Write a starting file for one of the course's labs, with the structure of the "
        "course's template (the encoder offsets, mycount, watched variables, printing from printing(), "
        "the Simulink PlotVars, the generation's includes), ready for 'crslab sim --lab FILE' (the "
        "final project's for 'crslab contest --lab FILE'). "
        + " ".join(f"{k}: {v}." for k, v in LABS.items()))
    p.add_argument("lab", choices=list(LABS), help="which lab")
    p.add_argument("file", type=Path, metavar="FILE", nargs="?",
                   help="the file to write (default: LAB.c, e.g. lab1.c); an existing file is kept")
    p.add_argument("-o", "--output", type=Path, metavar="FILE", help="the file to write (instead of FILE)")
    p.add_argument("--gen", choices=names, default=NEWEST.name,
                   help="framework generation: "
                   + "; ".join(f"{g.name}, {g.title} (printing with {g.print_call})" for g in GENERATIONS)
                   + " (default: %(default)s, the newest)")
    p.add_argument("--force", action="store_true", help="overwrite FILE if it exists")
    p.intermixed = True  # crslab new lab1 --gen A lab1.c
    p.set_defaults(func=run_new)


def run_new(args: argparse.Namespace) -> int:
    """``crslab new``."""
    if args.file is not None and args.output is not None:
        raise CliError("give the file once: FILE or -o FILE")
    path: Path = args.output or args.file or Path(f"{args.lab}.c")
    if path.suffix.lower() not in (".c", ".cpp"):
        raise CliError(f"{path}: a lab file is a .c file (crslab compiles .c, and .cpp holding C)")
    if path.is_dir():
        raise CliError(f"{path}: is a folder; give the lab file's name, e.g. {path / (args.lab + '.c')}")
    if path.exists() and not args.force:
        raise CliError(f"{path}: exists; not replacing it (--force overwrites it)")
    try:
        with_parent(path).write_text(starter_text(args.lab, args.gen))
    except OSError as exc:
        raise CliError(f"{path}: cannot write it ({exc.strerror})") from None
    print(f"crslab new: {path}: {LABS[args.lab]} for {named(args.gen).title}; run it with "
          f"'{RUN_WITH.get(args.lab, 'crslab sim --lab {path}').format(path=path)}'", file=sys.stderr)
    return 0
