"""The ``crslab`` command: one module per group of subcommands, registered in ``COMMANDS``.

Each command module (listed in ``COMMANDS`` with its commands) exposes ``register(subparsers)``,
which adds its parsers and sets ``func`` (``args -> exit status``). Expected failures raise
:class:`CliError` and become one line on stderr with status 2 (or the error's own status);
nothing prints a traceback.
"""

from __future__ import annotations

import argparse
import difflib
import importlib
import sys
from collections.abc import Sequence

from crslab.untrusted_text import for_terminal

COMMANDS: dict[str, tuple[str, ...]] = {
    "crslab.cli.kinematics_commands": ("fk", "ik"),
    "crslab.cli.sim_commands": ("sim",),
    "crslab.cli.debug_commands": ("debug",),
    "crslab.cli.scenario_commands": ("scenarios",),
    "crslab.cli.regress_commands": ("record", "check", "grade"),
    "crslab.cli.contest_commands": ("contest",),
    "crslab.cli.world_commands": ("world",),
    "crslab.cli.sweep_commands": ("sweep",),
    "crslab.cli.traj_commands": ("traj",),
    "crslab.cli.toolbox_commands": ("robots", "workspace", "rot"),
    "crslab.cli.scope_commands": ("vars", "plot"),
    "crslab.cli.serial_commands": ("map", "serial"),
    "crslab.cli.doctor_commands": ("doctor",),
    "crslab.cli.identify_commands": ("identify",),
    "crslab.cli.new_commands": ("new",),
    "crslab.cli.friction_commands": ("friction",),
    "crslab.cli.serve_commands": ("serve",),
}
"""Each command module and the commands its ``register`` adds (tests/test_cli_imports.py checks
the two agree). ``crslab COMMAND ...`` imports only COMMAND's module: each command's start pays
for its own imports (MuJoCo, numpy, a web server...), not for every other command's."""


class CliError(Exception):
    """An error the user can fix: printed as one line, exit status ``status``."""

    def __init__(self, message: str, status: int = 2) -> None:
        super().__init__(message)
        self.status = status


GROUPS = {
    "for students": ["sim", "debug", "record", "check", "new", "contest", "world", "scenarios", "vars",
                     "plot"],
    "for TAs and instructors": ["grade", "sweep", "serve", "identify", "friction"],
    "the course's host tools (MATLAB, Simulink, Tera Term)": ["serial", "map"],
    "the kinematics toolbox": ["fk", "ik", "traj", "robots", "workspace", "rot"],
    "this machine and this help": ["doctor", "help"],
}
"""How ``crslab --help`` lists the commands: by who uses them (every command in exactly one group)."""


def did_you_mean(word: str, choices: Sequence[str]) -> str:
    """`` (did you mean X?)`` when ``word`` is close to one of ``choices``, else nothing.

    >>> did_you_mean("--fsat", ["--fast", "--lab", "--speed"])
    ' (did you mean --fast?)'
    >>> did_you_mean("smi", ["sim", "debug"])
    ' (did you mean sim?)'
    >>> did_you_mean("--zzz", ["--fast"])
    ''
    """
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return f" (did you mean {close[0]}?)" if close else ""


class OneLineParser(argparse.ArgumentParser):
    """argparse, but a usage error is one line naming the command, its help and, for a mistyped
    option, the option it was probably meant to be."""

    intermixed = False
    """Options may come between the positional arguments (``crslab new lab1 --gen A lab1.c``)."""
    _intermixing = False
    _given: Sequence[str] = ()

    def error(self, message: str) -> None:  # type: ignore[override]
        unknown = [a for a in self._given if a.startswith("--") and a.split("=", 1)[0] not in self._options()]
        if message.startswith(("the following arguments are required", "one of the arguments")) and unknown:
            self.unrecognized(unknown)  # a mistyped option is likely the one that is missing
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")

    def _options(self) -> list[str]:
        return [o for a in self._actions for o in a.option_strings if o.startswith("--")]

    def parse_known_args(self, args: Sequence[str] | None = None,  # type: ignore[override]
                         namespace: argparse.Namespace | None = None) -> tuple[argparse.Namespace, list[str]]:
        self._given = list(args) if args is not None else []
        if self.intermixed and not self._intermixing:
            self._intermixing = True
            try:
                return self.parse_known_intermixed_args(args, namespace)
            finally:
                self._intermixing = False
        return super().parse_known_args(args, namespace)

    def unrecognized(self, extras: Sequence[str]) -> None:
        """The error for arguments this (sub)command does not take, with the nearest option."""
        first = extras[0]
        hint = did_you_mean(first.split("=", 1)[0], self._options()) if first.startswith("-") else ""
        word = "argument" if len(extras) == 1 else "arguments"
        self.error(f"unrecognized {word}: {' '.join(extras)}{hint}")


class CommandsParser(OneLineParser):
    """The ``crslab`` parser: its help lists the commands in :data:`GROUPS`."""

    commands: dict[str, OneLineParser]

    def format_help(self) -> str:
        helps = {a.dest: a.help or "" for a in self._subparsers_action()._choices_actions}
        lines = [self.format_usage().rstrip(), "", self.description or "", ""]
        width = max(map(len, helps)) + 2
        for title, names in GROUPS.items():
            lines.append(f"{title}:")
            lines += [f"  {name:<{width}}{helps.get(name, '')}" for name in names]
            lines.append("")
        lines += ["options:", "  -h, --help  show this help and exit", "  --version   show crslab's version",
                  "", "'crslab help COMMAND' or 'crslab COMMAND --help' shows a command's options."]
        return "\n".join(lines) + "\n"

    def _subparsers_action(self) -> argparse._SubParsersAction:
        return next(a for a in self._actions if isinstance(a, argparse._SubParsersAction))


def build_parser(command: str | None = None) -> CommandsParser:
    """The ``crslab`` parser with every registered subcommand, or with only the module of
    ``command`` (and ``help``) when ``command`` names one."""
    from crslab import __version__

    parser = CommandsParser(
        prog="crslab",
        description="Run a CRS robot lab's C file against a simulated arm, and the course's "
        "kinematics toolbox.",
    )
    parser.add_argument("--version", action="version", version=f"crslab {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=OneLineParser)
    modules = [m for m, names in COMMANDS.items() if command in names] or list(COMMANDS)
    for name in modules:
        importlib.import_module(name).register(sub)
    h = sub.add_parser("help", help="show the help of a command ('crslab help sim'), or this list")
    h.add_argument("topic", nargs="?", metavar="COMMAND", help="the command")
    h.set_defaults(func=lambda args: show_help(parser, args.topic))
    parser.commands = dict(sub.choices)
    return parser


def show_help(parser: CommandsParser, topic: str | None) -> int:
    """``crslab help [COMMAND]``."""
    if topic is None:
        parser.print_help()
        return 0
    command = parser.commands.get(topic)
    if command is None:
        raise CliError(f"no command {topic!r}{did_you_mean(topic, list(parser.commands))}; 'crslab help' "
                       "lists them")
    command.print_help()
    return 0


def innermost(parser: OneLineParser, argv: Sequence[str]) -> OneLineParser:
    """The (sub)command parser that ``argv`` names: ``crslab serial read ...`` is ``serial read``'s."""
    for word in argv:
        action = next((a for a in parser._actions if isinstance(a, argparse._SubParsersAction)), None)
        if action is None:
            break
        if word in action.choices:
            parser = action.choices[word]
    return parser


def _unknown_command(parser: CommandsParser, argv: Sequence[str]) -> str | None:
    """The error for a first word that is no command (with the nearest one), else None."""
    words = [a for a in argv if not a.startswith("-")]
    if not words or (argv and argv[0].startswith("-")) or words[0] in parser.commands:
        return None
    return f"crslab: error: no command {words[0]!r}{did_you_mean(words[0], list(parser.commands))} " \
           "(see 'crslab --help')"


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``crslab`` console script; returns the exit status."""
    from crslab.resources import ResourceError
    from crslab.run import termination

    if argv is None:  # the crslab command itself: --rrd's writer starts now (see rerun_writer)
        from crslab.sinks.rerun_writer import start_writer

        start_writer(sys.argv[1:])
        termination.install()  # SIGTERM and SIGHUP clean up as Ctrl-C does
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        parser = build_parser(argv[0] if argv else None)
    except ResourceError as exc:  # a broken installation: say how to repair it
        print(f"crslab: {exc}", file=sys.stderr)
        return 2
    unknown = _unknown_command(parser, argv)
    if unknown:
        print(unknown, file=sys.stderr)
        return 2
    args, extras = parser.parse_known_args(argv)
    if extras:  # said by the subcommand that was given them, with its nearest option
        innermost(parser, argv).unrecognized(extras)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        status = int(args.func(args) or 0)
    except CliError as exc:
        # a message may quote what a lab controls (a path it tried, a file's name): one safe line
        print(f"crslab {args.command}: {for_terminal(str(exc))}", file=sys.stderr)
        return exc.status
    except termination.Terminated as exc:
        print(f"crslab {args.command}: terminated ({exc.name})", file=sys.stderr)
        return termination.exit_status(exc.signum)
    except KeyboardInterrupt:
        print(f"crslab {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    return termination.exit_status(termination.received) if termination.received else status
