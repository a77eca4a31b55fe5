"""The ``crslab`` command: one module per group of subcommands, registered in ``COMMANDS``.

Each command module exposes ``register(subparsers)``, which adds its parsers and sets
``func`` (``args -> exit status``). Expected failures raise :class:`CliError` and become one
line on stderr with status 2 (or the error's own status); nothing prints a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

COMMANDS = [
    "crslab.cli.kinematics_commands",
    "crslab.cli.sim_commands",
    "crslab.cli.debug_commands",
    "crslab.cli.scenario_commands",
    "crslab.cli.regress_commands",
    "crslab.cli.sweep_commands",
    "crslab.cli.traj_commands",
    "crslab.cli.toolbox_commands",
    "crslab.cli.scope_commands",
    "crslab.cli.serial_commands",
    "crslab.cli.doctor_commands",
    "crslab.cli.identify_commands",
    "crslab.cli.serve_commands",
]


class CliError(Exception):
    """An error the user can fix: printed as one line, exit status ``status``."""

    def __init__(self, message: str, status: int = 2) -> None:
        super().__init__(message)
        self.status = status


class OneLineParser(argparse.ArgumentParser):
    """argparse, but a usage error is one line naming the command and the fix."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def build_parser() -> argparse.ArgumentParser:
    """The full ``crslab`` parser with every registered subcommand."""
    from crslab import __version__

    parser = OneLineParser(
        prog="crslab",
        description="Run a CRS robot lab's C file against a simulated arm, and the course's "
        "kinematics toolbox.",
    )
    parser.add_argument("--version", action="version", version=f"crslab {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=OneLineParser)
    for name in COMMANDS:
        importlib.import_module(name).register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``crslab`` console script; returns the exit status."""
    from crslab.resources import ResourceError

    if argv is None:  # the crslab command itself: --rrd's writer starts now (see rerun_writer)
        from crslab.sinks.rerun_writer import start_writer

        start_writer(sys.argv[1:])
    try:
        parser = build_parser()
    except ResourceError as exc:  # a broken installation: say how to repair it
        print(f"crslab: {exc}", file=sys.stderr)
        return 2
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except CliError as exc:
        print(f"crslab {args.command}: {exc}", file=sys.stderr)
        return exc.status
    except KeyboardInterrupt:
        print(f"crslab {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
