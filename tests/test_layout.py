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


# -- who may include whom, and call whom (docs/architecture.md: "C folders") ------------------------
MAY_USE = {"board": {"board", "port", "plant", "kin", "firmware"}, "plant": {"plant", "port", "kin"},
           "kin": {"kin"}, "port": {"port"}, "firmware": {"firmware", "port", "kin"}}
"""Each C folder and the folders it may include or call into: the board drives the plant and the
firmware; the plant, the firmware, the kinematics and the port include nothing above them."""
_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
_DEFINITION = re.compile(r"^(?!static\b)[A-Za-z_][\w \t*\n]*?\b([A-Za-z_]\w*)\s*\([^;{}()]*\)\s*\{", re.M)
_CALL = re.compile(r"\b([A-Za-z_]\w*)\s*\(")


def folder_of(path: Path) -> str:
    return path.relative_to(CSRC.resolve()).parts[0]


def sources(folder: str) -> list[Path]:
    """The C files of a folder of csrc/ (the firmware's C28x check shims left out)."""
    return sorted(p for p in (CSRC / folder).rglob("*")
                  if p.suffix in (".c", ".h") and "c28x_check" not in p.parts)


def defined_functions(text: str) -> set[str]:
    """The functions a C file defines for other files (not ``static``).

    >>> sorted(defined_functions("int f(int a)\\n{ return g(a); }\\nstatic void h(void) {}\\n"
    ...                          "const char *\\nname_of(int x) {\\n}\\nint k(void);\\n"))
    ['f', 'name_of']
    """
    return set(_DEFINITION.findall(_COMMENT.sub("", text)))


def called_functions(text: str) -> set[str]:
    """Every name a C file writes as a call (a superset: casts and macros too)."""
    return set(_CALL.findall(_COMMENT.sub("", text)))


@pytest.mark.parametrize("folder", sorted(set(MAY_USE) - {"firmware"}))
def test_each_folder_includes_only_what_it_may(folder):
    search = folders(build.INCLUDES)  # the native build's path: every folder is on it
    found = []
    for source in sources(folder):
        for line, name, quoted in includes(source.read_text()):
            where = resolve(source, name, quoted, search)
            inside = where is not None and where.is_relative_to(CSRC.resolve())
            if inside and folder_of(where) not in MAY_USE[folder]:
                found.append(f"{source.relative_to(CSRC)}:{line}: {name} ({folder_of(where)})")
    assert found == []


def calls_up(callers: dict[str, str], definers: dict[str, str]) -> list[str]:
    """Each call (file: name) of a file in ``callers`` (path: text) to a function only a folder it may
    not use defines (``definers``: path: text, every C file), as ``file: name (where it is defined)``."""
    by_folder: dict[str, set[str]] = {}
    for path, text in definers.items():
        by_folder.setdefault(path.split("/")[0], set()).update(defined_functions(text))
    found = []
    for path, text in callers.items():
        allowed = set().union(*(by_folder.get(f, set()) for f in MAY_USE[path.split("/")[0]]))
        for name in sorted(called_functions(text) - allowed):
            owners = sorted(f for f, names in by_folder.items() if name in names)
            if owners:
                found.append(f"{path}: {name} ({', '.join(owners)})")
    return found


def test_no_folder_calls_a_function_only_a_folder_above_it_defines():
    texts = {p.relative_to(CSRC).as_posix(): p.read_text() for f in MAY_USE for p in sources(f)}
    assert calls_up(texts, texts) == []


def test_a_call_up_is_found():
    texts = {"board/serial.c": "int crs_board_send(int n)\n{\n    return n;\n}\n",
             "firmware/print.c": "int print(void)\n{\n    return crs_board_send(3) + helper(1);\n}\n",
             "firmware/help.c": "int helper(int x) { return x; }\n",
             "plant/drive.c": "void step(void) { crs_board_send(0); kin_f(); }\n",
             "kin/k.c": "void kin_f(void) {}\n"}
    assert calls_up(texts, texts) == ["firmware/print.c: crs_board_send (board)",
                                      "plant/drive.c: crs_board_send (board)"]
