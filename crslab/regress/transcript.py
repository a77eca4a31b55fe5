"""Golden transcripts: the exact bytes a lab printed, after a small header, and the printed
lines with the simulated time each one was printed at.

A golden file written by ``crslab record``::

    # crslab transcript: the exact bytes the lab printed follow the '# ----' line
    # crslab: 0.1.0
    # lab: lab1.c
    # lab_sha256: 5f0c...
    # scenario: tour
    # scenario_sha256: 9a41...
    # end_s: 25.000
    # rest_motor_rad: 0 -0.42 0.24
    # startup_delay: yes
    # motor_board: none
    # plant: default
    # world: none
    # ----
    0.00 -24.06 13.75

A file without this header (say one ``crslab sim --transcript`` wrote) is a golden file too: all
of it is the transcript. What the header says about the run (scenario, duration, resting pose,
startup delay, motor board, plant file) is read by one function, :func:`recorded_run`, for
``crslab check`` and the ``crslab_check`` fixture alike. ``plant: default`` (or no ``plant``
line, as in files older than plant files) is crslab's own arm; a file name is found like a
scenario file's. ``world: none`` (or no ``world`` line, as in files older than worlds) is free air;
a built-in world's name or a world file (found like a scenario file) is the world it ran in.
"""

from __future__ import annotations

import bisect
import hashlib
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from crslab import serial_lines
from crslab.framework_facts import MOTOR_BOARDS, TICKS_PER_S
from crslab.output_paths import with_parent
from crslab.scenario.event import LONGEST_S
from crslab.toml_file import read_input, shown

MAGIC = b"# crslab transcript"
DEFAULT_PLANT = "default"
"""A golden header's ``plant`` for crslab's own arm."""
DEFAULT_WORLD = "none"
"""A golden header's ``world`` for free air (world ``none``)."""
HEADER_END = b"# ----\n"
GOLDEN_MAX_BYTES = 64_000_000
"""The largest golden file crslab reads: four times what a run prints at most by default
(``--max-output-mb 16``)."""


class GoldenError(ValueError):
    """A golden file that cannot be read; the message names the file."""


@dataclass(frozen=True)
class Line:
    """One printed line: its 1-based ``number``, its ``text`` (no line end) and the ``tick`` of the
    serial_printf call that printed its first byte (None when not known)."""

    number: int
    text: str
    tick: int | None = None

    @property
    def time(self) -> str:
        """The simulated time, as reports show it.

        >>> Line(3, "0.00", 4100).time
        't = 4.100 s'
        """
        return "t = ?" if self.tick is None else f"t = {self.tick / TICKS_PER_S:.3f} s"


@dataclass(frozen=True)
class Golden:
    """A golden file: its header fields and the transcript bytes."""

    path: Path
    header: dict[str, str] = field(default_factory=dict)
    body: bytes = b""
    lines: dict[str, int] = field(default_factory=dict, compare=False, repr=False)
    """The line of each header field (for errors naming it)."""

    def fail(self, key: str, why: str) -> GoldenError:
        """The error ``FILE:LINE: KEY: why`` for the header field ``key``."""
        line = self.lines.get(key)
        return GoldenError(f"{self.path}:{line}: {key}: {why}" if line else f"{self.path}: {key}: {why}")


def sha256_of(data: bytes) -> str:
    """Short content hash used in headers (16 hex digits of SHA-256).

    >>> sha256_of(b"")
    'e3b0c44298fc1c14'
    """
    return hashlib.sha256(data).hexdigest()[:16]


def split_lines(data: bytes, calls: Sequence[tuple[int, bytes]] | None = None) -> list[Line]:
    r"""The lines of a transcript (:mod:`crslab.serial_lines`' rule). With ``calls`` (the (tick,
    bytes) of each serial_printf call, whose bytes make up ``data``) every line gets its tick.

    >>> [(l.number, l.text, l.tick) for l in split_lines(b"a 1\n\rb", [(4100, b"a 1\n\r"), (4600, b"b")])]
    [(1, 'a 1', 4100), (2, 'b', 4600)]
    """
    starts: list[int] = []
    ticks: list[int] = []
    if calls is not None:
        offset = 0
        for tick, chunk in calls:
            starts.append(offset)
            ticks.append(tick)
            offset += len(chunk)

    def tick_at(pos: int) -> int | None:  # of the last call starting at or before pos
        return ticks[max(bisect.bisect_right(starts, pos) - 1, 0)] if starts else None

    return [Line(i + 1, text, tick_at(offset)) for i, (offset, text) in enumerate(serial_lines.split(data))]


@dataclass(frozen=True)
class RecordedRun:
    """The run options a golden file's header records; None where it records nothing."""

    scenario: str | None = None
    duration_s: float | None = None
    rest_motor_rad: tuple[float, float, float] | None = None
    startup_delay: bool | None = None
    motor_board: str | None = None
    plant: str | None = None
    """A plant file (found like a scenario file); None: crslab's own arm."""
    world: str | None = None
    """A built-in world's name or a world file (found like a scenario file); None: free air."""

    def overridden(self, *, scenario: str | None = None, duration_s: float | None = None,
                   rest_motor_rad: Sequence[float] | None = None,
                   startup_delay: bool | None = None, motor_board: str | None = None,
                   plant: str | None = None, world: str | None = None) -> RecordedRun:
        """The options to run with: each one given (not None) wins over the golden file's.

        >>> RecordedRun("tour", 25.0, (0.0, -0.4, 0.2), False, "none").overridden(duration_s=5.0)
        RecordedRun(scenario='tour', duration_s=5.0, rest_motor_rad=(0.0, -0.4, 0.2), startup_delay=False, \
motor_board='none', plant=None, world=None)
        """
        rest = tuple(float(v) for v in rest_motor_rad) if rest_motor_rad is not None else self.rest_motor_rad
        return RecordedRun(scenario if scenario is not None else self.scenario,
                           duration_s if duration_s is not None else self.duration_s,
                           rest,  # type: ignore[arg-type]
                           startup_delay if startup_delay is not None else self.startup_delay,
                           motor_board if motor_board is not None else self.motor_board,
                           plant if plant is not None else self.plant,
                           world if world is not None else self.world)


def find_scenario(name: str, folders: Sequence[Path]) -> str:
    """A scenario (or plant file) named in a header or a test: ``folder / name`` for the first folder that has
    such a file, else ``name`` itself (a built-in name, or a path the loader will check).

    >>> find_scenario("tour", [Path("/nonexistent")])
    'tour'
    """
    for folder in folders:
        candidate = Path(folder) / name
        if candidate.is_file():
            return str(candidate)
    return name


def recorded_run(golden: Golden, scenario_folders: Sequence[Path] = ()) -> RecordedRun:
    """What ``golden``'s header says its transcript was recorded with. A scenario file is looked
    for in ``scenario_folders`` (then the golden file's own folder). Raises :class:`GoldenError`
    naming the file and the field when a field is malformed.

    >>> g = Golden(Path("g.txt"), {"scenario": "tour", "end_s": "6.000",
    ...            "rest_motor_rad": "0.0 -0.35 0.3", "startup_delay": "no", "motor_board": "piccolo",
    ...            "plant": "default", "world": "contest"})
    >>> recorded_run(g)
    RecordedRun(scenario='tour', duration_s=6.0, rest_motor_rad=(0.0, -0.35, 0.3), startup_delay=False, \
motor_board='piccolo', plant=None, world='contest')
    >>> recorded_run(Golden(Path("g.txt"), {"startup_delay": "maybe"}, lines={"startup_delay": 7}))
    Traceback (most recent call last):
    ...
    crslab.regress.transcript.GoldenError: g.txt:7: startup_delay: must be yes or no, got 'maybe'
    """
    h, path = golden.header, golden.path
    scenario = h.get("scenario") or None
    if scenario is not None:
        scenario = find_scenario(scenario, [*scenario_folders, path.parent])
    duration = None
    if h.get("end_s"):
        duration = _header_number(h["end_s"])
        if duration is None or not 0 < duration <= LONGEST_S:
            raise golden.fail("end_s", f"must be a number of seconds above 0, at most {LONGEST_S:g}, "
                                       f"got {shown(h['end_s'])}")
    rest = None
    if "rest_motor_rad" in h:
        values = tuple(_header_number(v) for v in h["rest_motor_rad"].split())
        if len(values) != 3 or not all(v is not None and abs(v) <= math.pi for v in values):
            raise golden.fail("rest_motor_rad", f"must be three angles within +-pi rad, "
                                                f"got {shown(h['rest_motor_rad'])}")
        rest = values
    delay = {"yes": True, "no": False, None: None}.get(h.get("startup_delay"), "bad")
    if delay == "bad":
        raise golden.fail("startup_delay", f"must be yes or no, got {shown(h['startup_delay'])}")
    board = h.get("motor_board") or None
    if board is not None and board not in MOTOR_BOARDS:
        raise golden.fail("motor_board", f"must be one of {', '.join(MOTOR_BOARDS)}, got {shown(board)}")
    plant = h.get("plant") or None
    if plant == DEFAULT_PLANT:
        plant = None
    if plant is not None:
        plant = find_scenario(plant, [*scenario_folders, path.parent])
    world = h.get("world") or None
    if world == DEFAULT_WORLD:
        world = None
    if world is not None:
        world = find_scenario(world, [*scenario_folders, path.parent])
    return RecordedRun(scenario, duration, rest, delay, board, plant, world)  # type: ignore[arg-type]


def _header_number(text: str) -> float | None:
    """A header field's number: a finite one of at most 40 characters, else None.

    >>> _header_number("6.000"), _header_number("1e999"), _header_number("nan"), _header_number("9" * 400)
    (6.0, None, None, None)
    """
    if len(text) > 40:
        return None
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def make_header(fields: dict[str, str]) -> bytes:
    """The header block for ``fields`` (written in the given order)."""
    lines = [MAGIC + b": the exact bytes the lab printed follow the '# ----' line\n"]
    for key, value in fields.items():
        if "\n" in key or "\n" in value or ":" in key:
            raise ValueError(f"bad header field {key!r}: {value!r}")
        lines.append(f"# {key}: {value}\n".encode())
    return b"".join(lines) + HEADER_END


def write_golden(path: Path, fields: dict[str, str], transcript: bytes) -> None:
    """Write a golden file: the header, then the transcript bytes exactly."""
    with_parent(path).write_bytes(make_header(fields) + transcript)


def read_golden(path: Path) -> Golden:
    """Read a golden file (with or without a crslab header).

    >>> import tempfile, os
    >>> d = tempfile.mkdtemp(); p = Path(d) / "g.txt"
    >>> write_golden(p, {"scenario": "tour"}, b"1.00\\n\\r")
    >>> g = read_golden(p); g.header, g.body
    ({'scenario': 'tour'}, b'1.00\\n\\r')
    """
    if path.suffix.lower() in (".c", ".cpp", ".h", ".hpp", ".hh") and path.is_file():
        raise GoldenError(f"{path}: is a C file (a lab), not a golden transcript: record the lab's "
                          f"transcript with crslab record --lab {path} -o golden.txt, then check "
                          "against golden.txt")
    data = read_input(path, "golden file", GoldenError, max_bytes=GOLDEN_MAX_BYTES)
    if not data.startswith(MAGIC):
        return Golden(path, {}, data)
    end = data.find(b"\n" + HEADER_END)
    if end < 0:
        raise GoldenError(f"{path}: the crslab header has no end line ('# ----')")
    header: dict[str, str] = {}
    lines: dict[str, int] = {}
    for number, raw in enumerate(data[:end].split(b"\n")[1:], start=2):
        text = raw.decode("utf-8", "replace")
        key, sep, value = text[2:].partition(": ")
        if not text.startswith("# ") or not sep:
            raise GoldenError(f"{path}:{number}: header line must read '# key: value', got {shown(text)}")
        header[key.strip()] = value.strip()
        lines[key.strip()] = number
    return Golden(path, header, data[end + 1 + len(HEADER_END):], lines)
