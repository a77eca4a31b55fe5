"""``crslab doctor``: check that this machine has what a run needs, one line per item with a fix."""

from __future__ import annotations

import argparse
import sys

from crslab.os_support import SUPPORTED_PLATFORMS


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``doctor`` subcommand."""
    p = sub.add_parser(
        "doctor", help="check that this machine has what crslab needs, with a fix for what is missing",
        description="Check what a run needs and print one line per item with its fix: the platform "
        f"({SUPPORTED_PLATFORMS}), Python, a C compiler (CC, else cc, gcc or clang) and its version, that a "
        "lab compiles, links against the board and runs, that MuJoCo loads and steps the arm, that the "
        "build cache is writable; and for the live windows a display (--viewer), the rerun viewer "
        "(--rerun) and pseudo-terminals (--pty). Exit 0 when everything 'crslab sim' needs is here, "
        "1 otherwise.")
    p.set_defaults(func=run_doctor)


def run_doctor(args: argparse.Namespace) -> int:
    """``crslab doctor``."""
    from crslab.doctor import doctor

    def out(line: str) -> None:
        print(line, flush=True)

    if doctor(out):
        print("crslab doctor: everything 'crslab sim' needs is here", file=sys.stderr)
        return 0
    print("crslab doctor: 'crslab sim' cannot run here until the FAILED items are fixed "
          "(skipped items depend on them)", file=sys.stderr)
    return 1
