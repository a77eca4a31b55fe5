"""The one checked reader of crslab's input files: worlds, scenarios, plant files, tests files,
robots and friction tables (TOML), and the bytes of golden transcripts.

Whatever a file holds, reading it ends in the file's values or in one line naming the file, the
line and the key (``FILE:LINE: KEY: problem``), raised as the caller's own error; never in a
traceback, never in unbounded memory or time:

- a file is read only when it is a regular file of at most :data:`MAX_FILE_BYTES` (a golden
  file: its own limit), and only that many bytes are ever read;
- no value sits inside more than :data:`MAX_NESTING` tables and arrays (Python's TOML parser
  recurses once per level: a file of ``[[[[...`` is refused before it is parsed);
- a whole number is at most :data:`MAX_INTEGER` in size, and a number with a fraction or an
  exponent (a float) lies within :data:`SMALLEST` to :data:`LARGEST` in size, 0 and ``inf``
  aside, ``nan`` never: ``1e300``, ``1e-300`` and a 400-digit integer are refused at their line.

What each key means, and the range it may take, is the reader of that kind of file's
(:class:`Table`'s ``number(..., minimum=, maximum=)``); the bounds here hold for every file.

>>> doc = TomlFile.parse('name = "w"\\n[peg]\\nmass_kg = 1e-300\\n', "w.toml", ValueError)
Traceback (most recent call last):
...
ValueError: w.toml:3: peg.mass_kg: 1e-300 is too small a number (at least 1e-12 in size, or 0)
>>> doc = TomlFile.parse('name = "w"\\n[peg]\\nmass_kg = 0.03\\n', "w.toml", ValueError)
>>> peg = doc.table(("peg",), "peg")
>>> peg.number("mass_kg", minimum=0.001), peg.line_of("mass_kg")
(0.03, 3)
>>> peg.number("length_m")
Traceback (most recent call last):
...
ValueError: w.toml:2: peg.length_m: missing
"""

from __future__ import annotations

import errno
import math
import os
import re
import stat
import tomllib
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

MAX_FILE_BYTES = 1_000_000
"""The largest world, scenario, plant, tests, robot or friction-table file crslab reads (the
largest it ships is under 20 kB)."""
MAX_NESTING = 8
"""The most tables and arrays a value may sit inside (a scenario's ``[[event]]`` list of three
angles sits inside three: the events, its event, the list)."""
MAX_INTEGER = 2**63 - 1
"""The largest whole number, in size, a file may hold (a scenario's seed is at most this)."""
LARGEST = 1e12
"""The largest number with a fraction or an exponent, in size, a file may hold (``inf`` aside)."""
SMALLEST = 1e-12
"""The smallest such number, in size, a file may hold (0 aside)."""
SHOWN_CHARS = 60
"""How much of a value an error quotes."""

Error = Callable[[str], Exception]
"""The caller's error: given the one line, the exception to raise (``ScenarioError``, ...)."""
KeyPath = tuple[str | int, ...]
"""Where a value is: table and key names, and the index in an array (of tables)."""


def shown(value: object) -> str:
    """``repr(value)``, cut to :data:`SHOWN_CHARS` (an error never quotes a megabyte).

    >>> shown([1] * 100)
    '[1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,... (300 characters)'
    """
    text = repr(value)
    return text if len(text) <= SHOWN_CHARS else f"{text[:SHOWN_CHARS]}... ({len(text)} characters)"


def key_name(path: Iterable[str | int]) -> str:
    """A key's name in an error: its tables' and its own names, dotted (indices left out: the line
    says which).

    >>> key_name(("event", 3, "at")), key_name(("groove", "corners_xy_m", 2, 0))
    ('event.at', 'groove.corners_xy_m')
    """
    return ".".join(p for p in path if isinstance(p, str))


def read_input(path: Path, what: str, error: Error, *, shown_as: str | None = None,
               max_bytes: int = MAX_FILE_BYTES) -> bytes:
    """The bytes of the input file ``path`` (``what`` says what kind, ``shown_as`` how errors name
    it): a regular file of at most ``max_bytes``, of which no more is read. Anything else raises
    ``error`` with one line naming the file.

    >>> read_input(Path("/nonexistent/arm.toml"), "plant file", ValueError)
    Traceback (most recent call last):
    ...
    ValueError: /nonexistent/arm.toml: no such plant file
    >>> read_input(Path("/dev/zero"), "world file", ValueError)
    Traceback (most recent call last):
    ...
    ValueError: /dev/zero: is not a file (a world file is a regular file)
    """
    name = shown_as if shown_as is not None else str(path)
    try:
        # O_NONBLOCK: a FIFO named as the file is refused below, never waited on
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise error(f"{name}: no such {what}") from None
    except OSError as exc:
        if exc.errno in (errno.ENOTDIR, errno.ENAMETOOLONG, errno.ELOOP):
            raise error(f"{name}: no such {what}") from None
        raise error(f"{name}: cannot be read ({exc.strerror})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            kind = "a folder" if stat.S_ISDIR(st.st_mode) else "not a file"
            raise error(f"{name}: is {kind} (a {what} is a regular file)")
        chunks, size = [], 0
        while size <= max_bytes:
            chunk = os.read(fd, max_bytes + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        data = b"".join(chunks)
    except OSError as exc:
        raise error(f"{name}: cannot be read ({exc.strerror})") from None
    finally:
        os.close(fd)
    if len(data) > max_bytes:
        raise error(f"{name}: is larger than a {what} may be ({max_bytes:,} bytes at most)")
    return data


def decoded(data: bytes, source: str, error: Error) -> str:
    """``data`` as UTF-8 text; a byte that is not raises ``error`` naming its line.

    >>> decoded(b"a = 1\\nb = '\\xff'\\n", "x.toml", ValueError)
    Traceback (most recent call last):
    ...
    ValueError: x.toml:2: not UTF-8 text (byte 0xff)
    """
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise error(f"{source}:{line}: not UTF-8 text (byte 0x{data[exc.start]:02x})") from None


# -- the bounds every file keeps, checked before the file is parsed ------------------------------

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+(?:[ \t]*\.[ \t]*[A-Za-z0-9_-]+)*")
_DECIMAL = re.compile(r"[+-]?[0-9_]+")
_RADIX = re.compile(r"0x[0-9A-Fa-f_]+|0o[0-7_]+|0b[01_]+")
_FLOAT = re.compile(r"[+-]?(?:inf|nan|[0-9_]+(?:\.[0-9_]+)?(?:[eE][+-]?[0-9_]+)?)")
_VALUE_END = frozenset(",]}#\n\r\t ")


def number_problem(token: str) -> str | None:
    """Why the TOML number ``token`` is outside what a file may hold (see the module), else None
    (also for a token that is no number: the parser says what is wrong with it).

    >>> number_problem("9" * 400)
    'a whole number of 400 digits is too large (at most 9223372036854775807 in size)'
    >>> number_problem("1e300"), number_problem("-2e-300"), number_problem("1e-400")
    ('1e300 is too large a number (at most 1e+12 in size)', \
'-2e-300 is too small a number (at least 1e-12 in size, or 0)', \
'1e-400 is too small a number (at least 1e-12 in size, or 0)')
    >>> number_problem("nan"), number_problem("-inf"), number_problem("0.0"), number_problem("3_000")
    ('nan is not a number', None, None, None)
    """
    try:
        return _number_problem(token)
    except ValueError:  # no number after all ("_", "+"): the parser says what is wrong
        return None


def _number_problem(token: str) -> str | None:
    plain = token.replace("_", "")
    if _RADIX.fullmatch(token):
        digits = plain[2:]
        if len(digits) > 64 or int(digits, {"x": 16, "o": 8, "b": 2}[plain[1]]) > MAX_INTEGER:
            quoted = token if len(token) <= 20 else f"{token[:20]}..."
            return f"{quoted} is too large (at most {MAX_INTEGER} in size)"
        return None
    if _DECIMAL.fullmatch(token):
        digits = plain.lstrip("+-")
        if len(digits) > 19 or int(digits) > MAX_INTEGER:
            return f"a whole number of {len(digits)} digits is too large (at most {MAX_INTEGER} in size)"
        return None
    if not _FLOAT.fullmatch(token):
        return None
    if plain.lstrip("+-") == "nan":
        return f"{token} is not a number"
    if plain.lstrip("+-") == "inf":
        return None
    value = float(plain)
    quoted = token if len(token) <= 30 else f"{token[:30]}..."
    if math.isinf(value) or abs(value) > LARGEST:
        return f"{quoted} is too large a number (at most {LARGEST:g} in size)"
    mantissa = re.split("[eE]", plain)[0]
    if (value == 0 and re.search("[1-9]", mantissa)) or 0 < abs(value) < SMALLEST:
        return f"{quoted} is too small a number (at least {SMALLEST:g} in size, or 0)"
    return None


class _Scan:
    """One pass over a TOML text that finds the line of every key, table and array element and
    checks the bounds (nesting, numbers) before the parser sees the text. A text that is not TOML
    is passed over as well as can be: the parser says what is wrong with it."""

    def __init__(self, text: str, fail: Callable[[KeyPath, int, str], Exception]) -> None:
        self.t, self.i, self.line, self.fail = text, 0, 1, fail
        self.lines: dict[KeyPath, int] = {}
        self.arrays: dict[KeyPath, int] = {}  # an array of tables: how many tables so far
        self.table: KeyPath = ()

    # -- characters ---------------------------------------------------------------------------
    def _peek(self) -> str:
        return self.t[self.i] if self.i < len(self.t) else ""

    def _skip_blank(self, newlines: bool) -> None:
        """Past spaces (and newlines and comments, when ``newlines``)."""
        t = self.t
        while self.i < len(t):
            c = t[self.i]
            if c in " \t\r":
                self.i += 1
            elif c == "\n" and newlines:
                self.i += 1
                self.line += 1
            elif c == "#" and newlines:
                self._to_line_end()
            else:
                return

    def _to_line_end(self) -> None:
        end = self.t.find("\n", self.i)
        self.i = len(self.t) if end < 0 else end

    def _string(self) -> None:
        """Past one string (basic or literal, one line or many), counting its lines."""
        t, q = self.t, self.t[self.i]
        if t.startswith(q * 3, self.i):
            self.i += 3
            while self.i < len(t):
                c = t[self.i]
                if c == "\\" and q == '"':
                    self.line += t[self.i + 1:self.i + 2] == "\n"
                    self.i += 2
                elif c == "\n":
                    self.line += 1
                    self.i += 1
                elif t.startswith(q * 3, self.i):
                    while self.i < len(t) and t[self.i] == q:  # up to two quotes end the text
                        self.i += 1
                    return
                else:
                    self.i += 1
            return
        self.i += 1
        while self.i < len(t):
            c = t[self.i]
            if c == "\\" and q == '"':
                self.i += 2
            elif c == "\n":
                return
            else:
                self.i += 1
                if c == q:
                    return

    def _key_text(self, stops: str) -> str:
        """The text of a key, up to one of ``stops`` (or the line's end), its quotes included."""
        start = self.i
        while self.i < len(self.t) and self.t[self.i] not in stops and self.t[self.i] != "\n":
            if self.t[self.i] in "\"'":
                self._string()
            else:
                self.i += 1
        return self.t[start:self.i]

    @staticmethod
    def _names(text: str) -> tuple[str, ...] | None:
        """The names of a (dotted, maybe quoted) key; None when it is no key."""
        text = text.strip()
        if _BARE_KEY.fullmatch(text):
            return tuple(part.strip() for part in text.split("."))
        try:
            doc = tomllib.loads(f"{text} = 0")
        except tomllib.TOMLDecodeError:
            return None
        names: list[str] = []
        while isinstance(doc, dict) and len(doc) == 1:
            name, doc = next(iter(doc.items()))
            names.append(name)
        return tuple(names) if names else None

    # -- the document -------------------------------------------------------------------------
    def run(self) -> dict[KeyPath, int]:
        while True:
            self._skip_blank(newlines=True)
            if self.i >= len(self.t):
                return self.lines
            start = self.i
            if self._peek() == "[":
                self._header()
            else:
                self._key_value(self.table, "=")
            self._to_line_end()
            if self.i == start:  # never stuck: the parser will say what this is
                self.i += 1

    def _nest(self, path: KeyPath, line: int) -> None:
        """Refuse a table or an array at ``path`` that lies deeper than :data:`MAX_NESTING`."""
        if len(path) > MAX_NESTING:
            raise self.fail(path, line, f"nested too deep (a value sits inside at most {MAX_NESTING} "
                                        "tables and arrays)")

    def _header(self) -> None:
        line = self.line
        many = self.t.startswith("[[", self.i)
        self.i += 2 if many else 1
        names = self._names(self._key_text("]"))
        if names is None:
            return
        path: KeyPath = ()
        for n, name in enumerate(names):
            path += (name,)
            if path in self.arrays and not (many and n == len(names) - 1):
                path += (self.arrays[path] - 1,)  # a table of the last of an array of tables
        if many:
            self.lines.setdefault(path, line)
            self.arrays[path] = self.arrays.get(path, 0) + 1
            path += (self.arrays[path] - 1,)
        self._nest(path, line)
        self.lines.setdefault(path, line)
        self.table = path

    def _key_value(self, table: KeyPath, stops: str) -> None:
        line = self.line
        names = self._names(self._key_text(stops))
        if self._peek() != "=" or names is None:
            return
        self.i += 1
        path = table + names
        self._nest(path[:-1], line)
        self.lines.setdefault(path, line)  # the key's own line
        self._value(path)

    def _value(self, path: KeyPath) -> None:
        self._skip_blank(newlines=False)
        c = self._peek()
        if c in ("\"", "'"):
            self._string()
        elif c == "[":
            self._array(path)
        elif c == "{":
            self._inline_table(path)
        elif c:
            start = self.i
            while self.i < len(self.t) and self.t[self.i] not in _VALUE_END:
                self.i += 1
            problem = number_problem(self.t[start:self.i])
            if problem is not None:
                raise self.fail(path, self.line, problem)

    def _array(self, path: KeyPath) -> None:
        self._nest(path, self.line)
        self.i += 1
        index = 0
        while True:
            self._skip_blank(newlines=True)
            c = self._peek()
            if c in ("", "]"):
                self.i += 1
                return
            if c == ",":
                self.i += 1
                continue
            if c in "}=":  # not TOML: the parser says so
                return
            start = self.i
            self.lines.setdefault(path + (index,), self.line)
            self._value(path + (index,))
            index += 1
            if self.i == start:
                self.i += 1

    def _inline_table(self, path: KeyPath) -> None:
        self._nest(path, self.line)
        self.i += 1
        while True:
            self._skip_blank(newlines=True)
            c = self._peek()
            if c in ("", "}"):
                self.i += 1
                return
            if c == ",":
                self.i += 1
                continue
            if c == "]":
                return
            start = self.i
            self._key_value(path, "=,}")
            if self.i == start:
                self.i += 1


# -- the file and its tables ---------------------------------------------------------------------

_AT_LINE = re.compile(r"\s*\(at line (\d+), column \d+\)$")


@dataclass(frozen=True)
class TomlFile:
    """A checked TOML file: its values, and the line of each key, table and array element (for
    errors naming them)."""

    source: str
    """How errors name the file (a path as given, or a built-in's name)."""
    data: dict
    error: Error
    lines: dict[KeyPath, int] = field(repr=False)

    @classmethod
    def parse(cls, text: str, source: str, error: Error) -> TomlFile:
        """The file whose text is ``text``, checked (see the module); raises ``error`` with one line
        ``source:LINE: KEY: problem`` for anything wrong."""
        if len(text.encode("utf-8", "surrogatepass")) > MAX_FILE_BYTES:
            raise error(f"{source}: is larger than crslab reads ({MAX_FILE_BYTES:,} bytes at most)")

        def fail(path: KeyPath, line: int, why: str) -> Exception:
            return error(f"{source}:{line}: {key_name(path)}: {why}")

        lines = _Scan(text, fail).run()
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            message = str(exc)
            m = _AT_LINE.search(message)
            where = f"{source}:{m.group(1)}" if m else source
            raise error(f"{where}: not valid TOML: {_AT_LINE.sub('', message)}") from None
        except (RecursionError, ValueError, MemoryError) as exc:  # past the checks above: never
            raise error(f"{source}: cannot be read as TOML ({type(exc).__name__})") from None
        return cls(source, data, error, lines)

    @classmethod
    def read(cls, path: Path, what: str, error: Error, *, shown_as: str | None = None) -> TomlFile:
        """The TOML file at ``path`` (``what`` says what kind, ``shown_as`` how errors name it),
        read by :func:`read_input` and checked as :meth:`parse` checks."""
        source = shown_as if shown_as is not None else str(path)
        data = read_input(path, what, error, shown_as=source)
        return cls.parse(decoded(data, source, error), source, error)

    def line_of(self, path: KeyPath) -> int | None:
        """The line of the value at ``path``, else of the nearest table around it that has a line
        (a missing key: its table's header), else None (a missing top-level key)."""
        while path:
            if path in self.lines:
                return self.lines[path]
            path = path[:-1]
        return None

    def fail(self, path: KeyPath, why: str, name: str | None = None) -> Exception:
        """The error ``FILE:LINE: KEY: why`` for the value at ``path`` (``name``: how the key is
        named, else :func:`key_name`)."""
        line = self.line_of(path)
        where = f"{self.source}:{line}" if line else self.source
        name = key_name(path) if name is None else name
        return self.error(f"{where}: {name}: {why}" if name else f"{where}: {why}")

    def table(self, path: KeyPath = (), prefix: str | None = None) -> Table:
        """The table at ``path`` (the top level by default); its keys are named in errors after
        ``prefix`` and a dot (None: by their own names alone). A value there that is no table is
        refused."""
        values: object = self.data
        for part in path:
            values = values[part] if isinstance(values, dict | list) else None  # type: ignore[index]
        if not isinstance(values, dict):
            shown_name = key_name(path)
            raise self.fail(path, f"must be a table ([{shown_name}])", shown_name)
        return Table(self, path, values, prefix)

    def tables(self, name: str, prefix: str | None = None) -> list[Table]:
        """The tables of the array of tables ``[[name]]`` (none when the file has none)."""
        values = self.data.get(name, [])
        if not isinstance(values, list) or not all(isinstance(v, dict) for v in values):
            raise self.fail((name,), f"must be an array of tables ([[{name}]])", name)
        return [Table(self, (name, i), v, prefix) for i, v in enumerate(values)]


class Table:
    """One table of a checked file (:class:`TomlFile`): each value read with its type and range
    checked, each error one line naming the file, the key's line and the key."""

    def __init__(self, file: TomlFile, path: KeyPath, values: dict, prefix: str | None = None) -> None:
        self.file, self.path, self.table, self.prefix = file, path, values, prefix

    def name(self, key: str) -> str:
        """How errors name ``key`` of this table."""
        return f"{self.prefix}.{key}" if self.prefix else key

    def line_of(self, key: str) -> int | None:
        """The line where ``key`` is set (else this table's header's; None at the top level)."""
        return self.file.line_of((*self.path, key))

    def fail(self, key: str, why: str) -> Exception:
        """The error for ``key`` (several keys joined by ``|``: at the first one's line; a dotted
        key ``contact.egg``: in the table ``contact``)."""
        first = key.split("|")[0]
        path = (*self.path, first)
        if path not in self.file.lines:
            path = (*self.path, *first.split("."))
        return self.file.fail(path, why, self.name(key))

    def __contains__(self, key: str) -> bool:
        return key in self.table

    def check_keys(self, allowed: Iterable[str], required: Iterable[str] = ()) -> None:
        """Refuse a key not in ``allowed`` (named in the error in its order; a set's sorted) and a
        missing one of ``required`` (the first of the file's keys, then of ``required``, is named)."""
        named = sorted(allowed) if isinstance(allowed, set | frozenset) else list(allowed)
        for key in self.table:
            if key not in named:
                raise self.fail(key, f"unknown key (allowed: {', '.join(named)})")
        for key in required:
            if key not in self.table:
                raise self.fail(key, "missing")

    def value(self, key: str) -> object:
        """The raw value of ``key``; missing, it is refused."""
        if key not in self.table:
            raise self.fail(key, "missing")
        return self.table[key]

    def number(self, key: str, *, default: float | None = None, minimum: float | None = None,
               maximum: float | None = None, positive: bool = False, infinite: bool = False) -> float:
        """``key`` as a number (``default`` when left out, if given): at least ``minimum``, at most
        ``maximum``, above 0 when ``positive``; ``inf`` only when ``infinite``."""
        if key not in self.table and default is not None:
            return default
        return checked_number(self.value(key), lambda why: self.fail(key, why), minimum=minimum,
                              maximum=maximum, positive=positive, infinite=infinite)

    def integer(self, key: str, *, minimum: int | None = None, maximum: int | None = None) -> int:
        """``key`` as a whole number from ``minimum`` to ``maximum``."""
        value = self.value(key)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.fail(key, f"must be a whole number, got {shown(value)}")
        if (minimum is not None and value < minimum) or (maximum is not None and value > maximum):
            raise self.fail(key, f"must be from {minimum} to {maximum}, got {value!r}")
        return value

    def text(self, key: str) -> str:
        """``key`` as a string."""
        value = self.value(key)
        if not isinstance(value, str):
            raise self.fail(key, f"must be a string, got {shown(value)}")
        return value

    def boolean(self, key: str) -> bool:
        """``key`` as true or false."""
        value = self.value(key)
        if not isinstance(value, bool):
            raise self.fail(key, f"must be true or false, got {shown(value)}")
        return value

    def numbers(self, key: str, n: int, *, default: tuple | None = None, minimum: float | None = None,
                maximum: float | None = None, positive: bool = False) -> tuple[float, ...]:
        """``key`` as a list of ``n`` finite numbers, each in range as :meth:`number`'s."""
        if key not in self.table and default is not None:
            return default
        value = self.value(key)
        if (not isinstance(value, list) or len(value) != n
                or not all(isinstance(x, int | float) and not isinstance(x, bool) and math.isfinite(x)
                           for x in value)):
            raise self.fail(key, f"must be a list of {n} numbers, got {shown(value)}")
        out = []
        for x in value:
            out.append(checked_number(x, lambda why: self.fail(key, why), minimum=minimum, maximum=maximum,
                                      positive=positive, got=value))
        return tuple(out)

    def triple(self, key: str) -> np.ndarray:
        """``key`` as a list of three finite numbers (an array of 3 floats)."""
        if key not in self.table:
            raise self.fail(key, "missing")
        value = self.table[key]
        if (not isinstance(value, list) or len(value) != 3
                or not all(isinstance(x, int | float) and not isinstance(x, bool) for x in value)):
            raise self.fail(key, f"must be a list of three numbers, got {shown(value)}")
        return np.asarray(self.numbers(key, 3), dtype=float)

    def points(self, key: str, n: int, *, minimum: float | None = None,
               maximum: float | None = None) -> tuple[tuple[float, float], ...]:
        """``key`` as a list of ``n`` [x, y] points of finite numbers, each coordinate from
        ``minimum`` to ``maximum``."""
        value = self.value(key)
        if (not isinstance(value, list) or len(value) != n
                or not all(isinstance(p, list) and len(p) == 2
                           and all(isinstance(x, int | float) and not isinstance(x, bool) and math.isfinite(x)
                                   for x in p) for p in value)):
            raise self.fail(key, f"must be a list of {n} [x, y] points, got {shown(value)}")
        for p in value:
            for x in p:
                checked_number(x, lambda why: self.fail(key, why), minimum=minimum, maximum=maximum, got=p)
        return tuple((float(p[0]), float(p[1])) for p in value)

    def sub(self, key: str, prefix: str | None = None) -> Table:
        """The table ``key`` of this one."""
        return self.file.table((*self.path, key), prefix)


def checked_number(value: object, fail: Error, *, minimum: float | None = None, maximum: float | None = None,
                   positive: bool = False, infinite: bool = False, got: object = None) -> float:
    """``value`` as a float when it is a number in range (see :meth:`Table.number`), else
    ``fail(why)`` is raised (``got``: what the error quotes, by default the value).

    >>> checked_number(2, ValueError, minimum=0.0), checked_number(float("inf"), ValueError, infinite=True)
    (2.0, inf)
    >>> checked_number(-1, ValueError, positive=True)
    Traceback (most recent call last):
    ...
    ValueError: must be > 0, got -1
    """
    quoted = shown(value if got is None else got)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise fail(f"must be a number, got {quoted}")
    if math.isnan(value) or (math.isinf(value) and not infinite):
        raise fail(f"must be a number, got {quoted}")
    if positive and not value > 0:
        raise fail(f"must be > 0, got {quoted}")
    if minimum is not None and value < minimum:
        raise fail(f"must be at least {minimum:g}, got {quoted}")
    if maximum is not None and value > maximum:
        raise fail(f"must be at most {maximum:g}, got {quoted}")
    return float(value)


def read_toml(path: Path, what: str, error: Error) -> dict:
    """The values of the TOML file ``path``, checked (:meth:`TomlFile.read`): for a reader that
    walks them itself and names files in its errors.

    >>> read_toml(Path("/nonexistent/arm.toml"), "plant file", ValueError)
    Traceback (most recent call last):
    ...
    ValueError: /nonexistent/arm.toml: no such plant file
    """
    return TomlFile.read(path, what, error).data
