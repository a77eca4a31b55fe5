"""The firmware includes nothing of the board's: every ``#include`` of a file under csrc/firmware,
resolved as its builds resolve it (the WebAssembly firmware's include folders, a native build's,
and the C28x check's for its own headers), lands outside csrc/board and csrc/plant. What the two
sides share is csrc/port (docs/architecture.md)."""

import re
from pathlib import Path

import pytest

from crslab.lab import build, c28x_check, firmware

ROOT = Path(__file__).resolve().parents[1]
CSRC = ROOT / "csrc"
BOARD_SIDE = (CSRC / "board", CSRC / "plant")
_INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*([<"])([^>"\n]+)[>"]', re.MULTILINE)


def includes(text: str) -> list[tuple[int, str, bool]]:
    """Each ``#include`` of a C file: its line, the name, and whether it is quoted.

    >>> includes('#include "a.h"\\n  # include <b.h>\\n/* #include "c.h" */\\nx = "#include";')
    [(1, 'a.h', True), (2, 'b.h', False)]
    """
    return [(text.count("\n", 0, m.start()) + 1, m.group(2), m.group(1) == '"')
            for m in _INCLUDE.finditer(text)]


def folders(flags: list[str]) -> list[Path]:
    """The ``-I`` folders of a compiler's flags, in order."""
    return [Path(flags[i + 1]) for i, flag in enumerate(flags) if flag == "-I"]


def resolve(source: Path, name: str, quoted: bool, search: list[Path]) -> Path | None:
    """Where a compiler finds ``name`` included by ``source``: a quoted name first beside the file,
    then along ``search``; None when it is none of them (a system header)."""
    for folder in ([source.parent] if quoted else []) + search:
        if (folder / name).is_file():
            return (folder / name).resolve()
    return None


def board_includes(source: Path, search: list[Path]) -> list[tuple[int, str, str]]:
    """The includes of ``source`` that resolve into the board or the plant (line, name, where, under
    csrc/), or, quoted, nowhere (where: ``not found``)."""
    found = []
    for line, name, quoted in includes(source.read_text()):
        where = resolve(source, name, quoted, search)
        if where is None and quoted:
            found.append((line, name, "not found"))
        elif where is not None and any(where.is_relative_to(side.resolve()) for side in BOARD_SIDE):
            found.append((line, name, where.relative_to(CSRC.resolve()).as_posix()))
    return found


FIRMWARE_FILES = sorted(p for p in (CSRC / "firmware").rglob("*") if p.suffix in (".c", ".h"))
CHECK_FILES = sorted((CSRC / "firmware" / "c28x").rglob("*.h"))
BUILDS = {"wasm": folders(firmware.INCLUDES), "native": folders(build.INCLUDES)}


def test_the_firmware_has_files_and_its_build_no_board_folder():
    assert {p.name for p in FIRMWARE_FILES} >= {"firmware.c", "firmware.h", "serial_port.c", "coecsl.h"}
    assert CHECK_FILES
    wasm = [f.resolve() for f in BUILDS["wasm"]]
    assert (CSRC / "port").resolve() in wasm
    assert not any(f.is_relative_to(side.resolve()) for f in wasm for side in BOARD_SIDE)


@pytest.mark.parametrize("build_name", sorted(BUILDS))
def test_no_firmware_file_includes_a_board_header(build_name):
    found = [problem for source in FIRMWARE_FILES for problem in board_includes(source, BUILDS[build_name])]
    assert found == []


def test_the_c28x_checks_headers_include_nothing_of_the_boards():
    search = folders(c28x_check.include_dirs())
    assert [problem for source in CHECK_FILES for problem in board_includes(source, search)] == []


def test_a_firmware_file_that_includes_the_boards_header_is_found(tmp_path):
    source = tmp_path / "stand_in.c"
    source.write_text('#include "firmware.h"\n#include <stdint.h>\n#include "board.h"\n#include "hand.h"\n'
                      '#include "no_such.h"\n')
    search = [CSRC / "firmware", *BUILDS["native"]]
    assert board_includes(source, search) == [(3, "board.h", "board/board.h"), (4, "hand.h", "plant/hand.h"),
                                              (5, "no_such.h", "not found")]
    # the WebAssembly firmware's build cannot find the board's headers at all
    assert board_includes(source, [CSRC / "firmware", *BUILDS["wasm"]]) == [
        (3, "board.h", "not found"), (4, "hand.h", "not found"), (5, "no_such.h", "not found")]
