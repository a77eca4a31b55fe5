"""A CCS-style linker map of a lab's variables, which the course's ``parseMap`` reads, and
crslab's own reading of one (for ``crslab serial``).

The course's scripts find a variable's address in the map CCS writes next to the build
(docs/host-tools.md, "The map parseMap reads"): the first line naming ``.my_arrs`` (and
``.my_vars``) gives the section's origin and length as its third and fourth words, and the table after
``GLOBAL SYMBOLS: SORTED BY Symbol Address`` gives each symbol's page, 8-hex-digit address and
name with the COFF ABI's leading underscore; those inside either section are the variables the
scripts can read and write. :func:`write_map` writes those parts as the TI linker does (section
allocation map, both global symbol tables), for every section of the lab's data.

>>> from crslab.generations import GEN_B
>>> from crslab.lab.c28x_memory import layout
>>> from crslab.lab.variables import find_variables
>>> mem = layout(find_variables('#pragma DATA_SECTION(Kp1, ".my_vars")\\nfloat Kp1 = 12.5;'), GEN_B, "pd")
>>> text = write_map(mem, "pd.c")
>>> [line for line in text.splitlines() if ".my_vars" in line]
['.my_vars   1    0000d000    00000002     UNINITIALIZED', '                  0000d000    00000002     \
pd.obj (.my_vars)']
>>> read_map(text)["Kp1"]
53248
"""

from __future__ import annotations

import re
from pathlib import Path

from crslab import __version__
from crslab.lab.c28x_memory import PAGE, MemoryLayout

SYMBOL_TABLE = "GLOBAL SYMBOLS: SORTED BY Symbol Address"
"""The heading the course's parser looks for before the symbol table it reads."""
_RULE = "*" * 78


class MapError(Exception):
    """A map file that cannot be read, or names no such variable."""


def _symbol_table(title: str, rows: list[tuple[int, str]]) -> list[str]:
    out = [f"{title} ", "", f"{'page':<6}{'address':<10}{'name':<30}",
           f"{'----':<6}{'-------':<10}{'----':<30}"]
    out += [f"{PAGE:<6}{address:08x}  _{name}" for address, name in rows]
    return out + [""]


def write_map(mem: MemoryLayout, lab_file: str) -> str:
    """The map text of ``mem`` for the lab file named ``lab_file`` (CRLF line ends, as CCS writes)."""
    stem = Path(lab_file).stem
    lines = [
        _RULE,
        f"{'crslab ' + __version__ + ': simulated TMS320C2000 linker map':^78}",
        _RULE,
        f">> Data of {lab_file} as the TI linker lays it out on the simulated F28335 (COFF ABI).",
        "",
        f"OUTPUT FILE NAME:   <{stem}.out>",
        "",
        "",
        "SECTION ALLOCATION MAP",
        "",
        " output                                  attributes/",
        "section   page    origin      length       input sections",
        "--------  ----  ----------  ----------   ----------------",
    ]
    for s in mem.sections:
        lines.append(f"{s.name:<11}{PAGE:<5}{s.origin:08x}    {s.length:08x}     UNINITIALIZED")
        for origin, length, obj in s.inputs:
            lines.append(f"{'':<18}{origin:08x}    {length:08x}     {obj} ({s.name})")
        lines.append("")
    lines.append("")
    symbols = [(v.address, v.name) for v in mem.symbols()]
    by_name = sorted(symbols, key=lambda r: r[1])
    lines += _symbol_table("GLOBAL SYMBOLS: SORTED ALPHABETICALLY BY Name", by_name)
    lines += _symbol_table(SYMBOL_TABLE, sorted(symbols))
    lines.append(f"[{len(symbols)} symbols]")
    return "\r\n".join(lines) + "\r\n"


_SYMBOL_ROW = re.compile(r"^\s*\d+\s+([0-9A-Fa-f]{8})\s+_(\w+)\s*$")


def read_map(text: str) -> dict[str, int]:
    """Every symbol of a map's ``GLOBAL SYMBOLS: SORTED BY Symbol Address`` table: name (leading
    underscore stripped) -> 16-bit-word address. Raises :class:`MapError` when there is no table."""
    at = text.find(SYMBOL_TABLE)
    if at < 0:
        raise MapError(f"no '{SYMBOL_TABLE}' table: not a TI linker map")
    out = {}
    for line in text[at:].splitlines():
        m = _SYMBOL_ROW.match(line)
        if m:
            out[m.group(2)] = int(m.group(1), 16)
    return out


def read_map_file(path: Path) -> dict[str, int]:
    """:func:`read_map` of a file; a missing or unreadable file is a :class:`MapError`."""
    try:
        text = Path(path).read_text(errors="replace")
    except OSError as exc:
        raise MapError(f"{path}: cannot be read ({exc.strerror})") from None
    try:
        return read_map(text)
    except MapError as exc:
        raise MapError(f"{path}: {exc}") from None
