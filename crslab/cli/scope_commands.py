"""``crslab vars`` (a lab file's watched variables) and ``crslab plot`` (a ``--csv`` file as a figure)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from crslab.cli import CliError


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``vars`` and ``plot`` subcommands."""
    p = sub.add_parser(
        "vars",
        help="list a lab file's watched (#pragma DATA_SECTION) variables",
        description="List the variables a lab file places in the course's .my_vars / .my_arrs sections "
        "with #pragma DATA_SECTION, as ME446_serial_ListVars does: name, address on the simulated "
        "F28335 (16-bit words, as in 'crslab map'), C type, array length and initial value. While "
        "'crslab sim' runs, type 'get NAME', 'set NAME VALUE', 'set NAME[i] VALUE' or 'list' on its "
        "standard input to read and write them, or use 'crslab serial' / the course's MATLAB scripts "
        "with 'crslab sim --serial-dir'.",
    )
    p.add_argument("--lab", type=Path, metavar="FILE", help="the lab file (default: crslab's Lab 1)")
    p.add_argument("--all", action="store_true",
                   help="every global of the file (section .ebss, .econst or its DATA_SECTION), not only "
                   "the DATA_SECTION ones")
    p.add_argument("--json", action="store_true", help="print the list as JSON")
    p.set_defaults(func=run_vars)

    p = sub.add_parser(
        "plot",
        help="draw a 'crslab sim --csv' file as a figure for a lab report",
        description="Draw the signals of a 'crslab sim --csv' file, one panel per group (motor angles, "
        "torques, Simulink_PlotVar1..4, safety flag and LEDs, arm pose), with labelled units.",
    )
    p.add_argument("csv", type=Path, metavar="FILE.csv", help="a file written by 'crslab sim --csv'")
    p.add_argument("-o", "--output", type=Path, metavar="FIG",
                   help="the image to write, format from its suffix (.png, .pdf, .svg; default: FILE.png)")
    p.add_argument("--from", dest="t_from", type=float, metavar="SECONDS", help="start of the time window")
    p.add_argument("--to", dest="t_to", type=float, metavar="SECONDS", help="end of the time window")
    p.add_argument("--title", help="the figure's title (default: the CSV's file name)")
    p.set_defaults(func=run_plot)


def watched_rows(lab: Path | None, every: bool = False) -> list[dict]:
    """The watched variables of ``lab`` (default: crslab's Lab 1) as rows for the listing, with
    their C28x addresses (``every``: all its globals)."""
    from crslab.cli.serial_commands import lab_layout
    from crslab.lab.includes import own_variables

    path, text, mem = lab_layout(lab)
    rows = []
    for v in own_variables(path, text):
        if not every and (v.section is None or v.pointer or v.const):
            continue
        if v.initial is not None:
            initial = " ".join(v.initial.split())
        else:
            initial = "0" if v.length is None else "all 0"  # C zeroes globals without an initialiser
        placed = mem.find(v.name)
        rows.append({"name": v.name, "address": f"{placed.address:08x}" if placed else None,
                     "type": v.ctype + (" *" if v.pointer else ""), "length": v.length, "initial": initial,
                     "section": placed.section if placed else v.section, "static": v.static,
                     "line": v.line, "file": v.file})  # file: a header of the lab's own, or empty
    return rows


def run_vars(args: argparse.Namespace) -> int:
    """``crslab vars``."""
    rows = watched_rows(args.lab, every=args.all)
    if args.json:
        print(json.dumps(rows, indent=1))
        return 0
    if not rows:
        name = args.lab or "crslab's Lab 1"
        what = "global" if args.all else "#pragma DATA_SECTION"
        print(f"crslab vars: {name} has no {what} variables", file=sys.stderr)
        return 0
    table = [("name", "address", "type", "length", "initial", "line")]
    table += [(r["name"], r["address"] or "-", r["type"], "-" if r["length"] is None else str(r["length"]),
               r["initial"], f"{r['file']}:{r['line']}" if r["file"] else str(r["line"])) for r in rows]
    if args.all:
        table = [row[:2] + (section,) + row[2:] for row, section in
                 zip(table, ["section"] + [r["section"] + (" static" if r["static"] else "") for r in rows])]
    widths = [max(len(row[i]) for row in table) for i in range(len(table[0]) - 1)]
    for row in table:
        print("  ".join(cell.ljust(w) for cell, w in zip(row, widths)) + "  " + row[-1])
    return 0


def run_plot(args: argparse.Namespace) -> int:
    """``crslab plot``."""
    from crslab.scopes.plot import PlotError, plot_scope_csv

    out = args.output or args.csv.with_suffix(".png")
    try:
        panels = plot_scope_csv(args.csv, out, t_from=args.t_from, t_to=args.t_to, title=args.title)
    except PlotError as exc:
        raise CliError(str(exc)) from None
    print(f"crslab plot: {out}: {len(panels)} panels ({', '.join(panels)})", file=sys.stderr)
    return 0
