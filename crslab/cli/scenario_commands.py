"""``crslab scenarios``: list the built-in scenarios, or check one and show its timeline."""

from __future__ import annotations

import argparse

from crslab.cli import CliError
from crslab.framework_facts import TICKS_PER_S
from crslab.scenario.load import DEFAULT_SCENARIO, ScenarioError, describe_builtins, load_scenario


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``scenarios`` subcommand."""
    p = sub.add_parser("scenarios", help="list the built-in scenarios, or check one and show its timeline",
                       description="With no argument: every built-in scenario, one line each. With a "
                       "built-in name or a TOML file: check it (errors name file, line and key) and print "
                       "its timeline. The format is in docs/scenarios.md.")
    p.add_argument("scenario", nargs="?", metavar="NAME|FILE", help="a built-in scenario or a TOML file")
    p.set_defaults(func=run_scenarios)


def timeline(name_or_path: str) -> list[str]:
    """One line per event of a scenario, in the order they happen.

    >>> print(timeline("tour")[1])  # doctest: +NORMALIZE_WHITESPACE
    5.000 s  hand to motor (0.00, 0.00, 0.00) = DH (0.00, -90.00, 90.00) deg over 2 s
    (there at t = 7.0 s)  (line 11)
    """
    s = load_scenario(name_or_path)
    out = [f"{s.name}: {s.description}" if s.description else s.name]
    if s.rest_motor_rad is not None:
        out.append(f"   resting pose (motor, rad): {' '.join(f'{v:g}' for v in s.rest_motor_rad)}")
    for e in s.events:
        line = f"  (line {e.line})" if e.line else ""
        out.append(f"{e.tick / TICKS_PER_S:8.3f} s  {e.describe()}{line}")
    out.append(f"{s.end_tick / TICKS_PER_S:8.3f} s  end (seed {s.seed})")
    return out


def run_scenarios(args: argparse.Namespace) -> int:
    """``crslab scenarios``."""
    try:
        if args.scenario is None:
            rows = describe_builtins()
            width = max(len(n) for n, _ in rows)
            for name, description in rows:
                tag = " (default)" if name == DEFAULT_SCENARIO and "default" not in description else ""
                print(f"{name:<{width}}  {description}{tag}")
        else:
            print("\n".join(timeline(args.scenario)))
    except ScenarioError as exc:
        raise CliError(str(exc)) from None
    return 0
