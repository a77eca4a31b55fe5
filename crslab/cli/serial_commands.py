"""``crslab map`` (the CCS-style map of a lab's variables) and ``crslab serial`` (read, write and
scope a running lab over its serial ports, as the course's MATLAB scripts and Simulink model do)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from crslab.cli import CliError
from crslab.framework_facts import SIMULINK_INPUTS, SIMULINK_PERIOD_MS
from crslab.generations import GENERATIONS
from crslab.host_tools.client import MATLAB_TIMEOUT_S, LinkError, SerialLink, read_floats, write_float
from crslab.host_tools.linker_map import MapError, read_map_file, write_map
from crslab.host_tools.serial_protocols import ADDRESS_MASK, MAX_FLOATS
from crslab.lab.build import lab_memory
from crslab.lab.c28x_memory import MemoryLayout
from crslab.output_paths import with_parent


def lab_layout(lab: Path | None) -> tuple[Path, str, MemoryLayout]:
    """The lab file (default: crslab's Lab 1), its text and its variables' layout, read from its
    text (no build needed: the layout depends on the text alone)."""
    from crslab.lab.build import DEFAULT_LAB, LabBuildError
    from crslab.lab.lab_file import read_lab_file

    path = lab if lab is not None else DEFAULT_LAB
    try:
        text = read_lab_file(path).decode("utf-8", "replace")
    except LabBuildError as exc:
        raise CliError(str(exc)) from None
    return path, text, lab_memory(path, text)


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``map`` and ``serial`` subcommands."""
    p = sub.add_parser(
        "map",
        help="write the CCS-style linker map of a lab's variables (what the course's parseMap reads)",
        description="Write the linker map the course's MATLAB scripts parse to find a variable's address: "
        "the section allocation map (.ebss, .my_vars, .my_arrs with their origin and length) and the "
        "global symbols with their 16-bit-word addresses on the simulated F28335, as 'crslab sim' "
        "lays them out. Put it where the scripts look ("
        + ", ".join(f"Gen {g.name}: {g.map_folder}" for g in GENERATIONS) + ").",
    )
    p.add_argument("--lab", type=Path, metavar="FILE", help="the lab file (default: crslab's Lab 1)")
    p.add_argument("-o", "--output", type=Path, metavar="FILE.map",
                   help="where to write it (default: stdout)")
    p.set_defaults(func=run_map)

    p = sub.add_parser(
        "serial",
        help="read, write and scope a running lab over its serial ports (as MATLAB and Simulink do)",
        description="Talk to a running 'crslab sim --serial-dir DIR' (or --serial-tcp), or to the real "
        "board, with the course's own protocols: read and write variables over SerialC as "
        "ME446_serialread / ME446_serialwrite do, or exchange Simulink's 5 ms packets over SerialB and "
        "plot the four PlotVars.",
    )
    verbs = p.add_subparsers(dest="verb", metavar="VERB", parser_class=type(p))
    r = verbs.add_parser("read", help="read N floats from a variable's address on (SerialC)",
                         description="Read N floats from NAME's address on, as ME446_serialread does (the "
                         "board steps two words per float and runs on into the next variables).")
    r.add_argument("name", metavar="NAME", help="a variable of the map (or a hex address such as 0xc816)")
    r.add_argument("count", metavar="N", type=int, nargs="?", default=1, help="floats to read (default 1)")
    _add_link_options(r, "SerialC")
    r.set_defaults(func=run_read)
    w = verbs.add_parser("write", help="write a float into a variable (SerialC)",
                         description="Write VALUE as a float at NAME's address, as ME446_serialwrite does "
                         "(an int or long variable gets the float's bit pattern, as on the board); the lab "
                         "sees it from its next tick. The value is then read back.")
    w.add_argument("name", metavar="NAME", help="a variable of the map (or a hex address such as 0xc816)")
    w.add_argument("value", metavar="VALUE", type=float, help="the value")
    w.add_argument("--no-read-back", action="store_true", help="do not read the value back")
    _add_link_options(w, "SerialC")
    w.set_defaults(func=run_write)
    s = verbs.add_parser("scope",
                         help="exchange Simulink's packets every 5 ms and plot PlotVar1..4 (SerialB)",
                         description="Be the course's Simulink model on SerialB: every 5 ms send FF 7F and "
                         "seven int16 values (SIMU_Var1..7_fromSIMU_16bit on the board), and plot the four "
                         "Simulink_PlotVars that come back (x 0.0001) in the rerun viewer.")
    s.add_argument("--simu", type=int, nargs=SIMULINK_INPUTS, metavar="V", default=[0] * SIMULINK_INPUTS,
                   help=f"the {SIMULINK_INPUTS} int16 values to send (default all 0; the course's model "
                   "sends 1s until its gains are tuned)")
    s.add_argument("--duration", type=float, metavar="SECONDS", help="stop after this many seconds")
    s.add_argument("--count", type=int, metavar="N", help="stop after N replies")
    s.add_argument("--print", dest="print_values", action="store_true",
                   help="print each reply (time in s, PlotVar1..4) instead of plotting")
    s.add_argument("-o", "--rrd", type=Path, metavar="FILE",
                   help="save the plot as a rerun recording (headless)")
    _add_link_options(s, "SerialB", needs_map=False)
    s.set_defaults(func=run_scope)
    o = verbs.add_parser("octave", help="where crslab's files for running the course's scripts in Octave are",
                         description="Print the folder of crslab's Octave compat files (serial, serialport, "
                         "instrfind, hex2dec, MException for GNU Octave with instrument-control) and the "
                         "line that loads them, so the course's MATLAB scripts run with only the port name "
                         "changed.")
    o.set_defaults(func=run_octave)
    p.set_defaults(func=lambda args: _missing_verb(p))


def _missing_verb(p: argparse.ArgumentParser) -> int:
    p.print_help(sys.stderr)
    return 2


def _add_link_options(p: argparse.ArgumentParser, port: str, needs_map: bool = True) -> None:
    g = p.add_argument_group("where the board is")
    g.add_argument("--dir", type=Path, metavar="DIR",
                   help=f"the --serial-dir of the running 'crslab sim': its {port}"
                   + (" and the map in it" if needs_map else ""))
    g.add_argument("--port", type=Path, metavar="PATH",
                   help=f"{port}'s serial port (a pty, or the real board's)")
    g.add_argument("--tcp", metavar="[HOST:]PORT", help=f"{port}'s TCP port of 'crslab sim --serial-tcp'")
    if needs_map:
        g.add_argument("--map", type=Path, metavar="FILE",
                       help="the map to find NAME in (default: the one in DIR)")
        g.add_argument("--lab", type=Path, metavar="FILE", help="find NAME in this lab file's layout instead")
    g.add_argument("--timeout", type=float, default=MATLAB_TIMEOUT_S, metavar="SECONDS",
                   help="how long to wait for each reply (default: %(default)g, MATLAB's)")
    p.set_defaults(port_name=port)


def no_serial_dir(folder: Path) -> str:
    """The error for a ``--dir`` that is not there.

    >>> no_serial_dir(Path("nope"))
    "--dir nope: no such folder (start 'crslab sim --serial-dir nope' first; it makes the folder)"
    """
    return (f"--dir {folder}: no such folder (start 'crslab sim --serial-dir {folder}' first; "
            "it makes the folder)")


def _open_link(args: argparse.Namespace) -> SerialLink:
    if args.tcp is not None:
        return SerialLink(tcp=args.tcp)
    path = args.port or (args.dir / args.port_name if args.dir is not None else None)
    if path is None:
        raise CliError("say where the board is: --dir DIR (of 'crslab sim --serial-dir DIR'), --port PATH or "
                       "--tcp PORT")
    if args.port is None and args.dir is not None and not Path(args.dir).is_dir():
        raise CliError(no_serial_dir(args.dir))
    if not Path(path).exists():
        raise CliError(f"{path}: no such port (is 'crslab sim --serial-dir' running?)")
    return SerialLink(path=Path(path))


def _address(args: argparse.Namespace) -> int:
    """NAME's address from the map (or the lab file, or NAME itself when it is a hex address)."""
    name = args.name
    if name.lower().startswith("0x"):
        try:
            address = int(name, 16)
        except ValueError:
            raise CliError(f"{name} is not a hex address") from None
        if not 0 <= address <= ADDRESS_MASK:
            raise CliError(f"{name} is beyond the C28x's 22-bit data addresses")
        return address
    if args.lab is not None:
        path, _, mem = lab_layout(args.lab)
        found = mem.find(name)
        if found is None:
            raise CliError(f"{path.name} defines no variable {name} crslab can lay out")
        return found.address
    map_path = args.map
    if map_path is None:
        if args.dir is None:
            raise CliError("say where to find NAME: --map FILE, --lab FILE, or --dir DIR (which holds "
                           "the map)")
        if not Path(args.dir).is_dir():
            raise CliError(no_serial_dir(args.dir))
        maps = sorted(Path(args.dir).glob("*.map"))
        if len(maps) != 1:
            raise CliError(f"{args.dir}: {'no' if not maps else len(maps)} .map files (give --map FILE)")
        map_path = maps[0]
    try:
        symbols = read_map_file(map_path)
    except MapError as exc:
        raise CliError(str(exc)) from None
    if name not in symbols:
        known = ", ".join(sorted(symbols)[:12]) + (", ..." if len(symbols) > 12 else "")
        raise CliError(f"no variable {name} in {map_path} (it has {known or 'none'})")
    return symbols[name]


def run_map(args: argparse.Namespace) -> int:
    """``crslab map``."""
    path, _, mem = lab_layout(args.lab)
    text = write_map(mem, path.name)
    if args.output is None:
        sys.stdout.write(text.replace("\r\n", "\n"))
        return 0
    try:
        with_parent(args.output).write_bytes(text.encode())
    except OSError as exc:
        raise CliError(f"{args.output}: cannot write the map ({exc.strerror})") from None
    print(f"crslab map: {args.output}: {len(mem.symbols())} symbols of {path.name}", file=sys.stderr)
    return 0


def run_octave(args: argparse.Namespace) -> int:
    """``crslab serial octave``."""
    from crslab.resources import path

    folder = path("octave")
    print(folder)
    print(f"crslab serial octave: in Octave, run once per session: addpath('{folder}'); crs_octave_compat()",
          file=sys.stderr)
    return 0


def run_read(args: argparse.Namespace) -> int:
    """``crslab serial read``."""
    if not 1 <= args.count <= MAX_FLOATS:
        raise CliError(f"N must be 1 to {MAX_FLOATS}, not {args.count}")
    address = _address(args)
    try:
        with _open_link(args) as link:
            values = read_floats(link, address, args.count, args.timeout)
    except LinkError as exc:
        raise CliError(str(exc)) from None
    for v in values:
        print(f"{v:.9g}")
    return 0


def run_write(args: argparse.Namespace) -> int:
    """``crslab serial write``."""
    address = _address(args)
    try:
        with _open_link(args) as link:
            write_float(link, address, args.value)
            if args.no_read_back:
                return 0
            [back] = read_floats(link, address, 1, args.timeout)
    except LinkError as exc:
        raise CliError(str(exc)) from None
    print(f"{args.name} = {back:.9g}   (read back at {address:08x})")
    return 0


def run_scope(args: argparse.Namespace) -> int:
    """``crslab serial scope``."""
    from crslab.host_tools.scope import RerunScope
    from crslab.host_tools.scope import run_scope as exchange_packets

    if any(not -32768 <= v <= 65535 for v in args.simu):
        raise CliError("--simu values are int16 (-32768..32767)")
    status = lambda line: print(f"crslab serial scope: {line}", file=sys.stderr)  # noqa: E731
    plot = None
    if args.print_values:
        def sample(t_s: float, values: tuple[float, ...]) -> None:
            print(f"{t_s:.3f} " + " ".join(f"{v:.4f}" for v in values), flush=True)
    else:
        plot = RerunScope("crslab serial scope", spawn=args.rrd is None,
                          rrd_path=str(args.rrd) if args.rrd else None, on_status=status)
        sample = plot
    try:
        with _open_link(args) as link:
            status(f"sending a packet every {SIMULINK_PERIOD_MS} ms on {link.name} (Ctrl-C stops)")
            n = exchange_packets(link, args.simu, sample, count=args.count, duration_s=args.duration)
    except LinkError as exc:
        raise CliError(str(exc)) from None
    except KeyboardInterrupt:
        n = None
    finally:
        if plot is not None:
            plot.close()
    if n is not None:
        status(f"{n} replies")
    return 0
