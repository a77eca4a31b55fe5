"""The one checked reader of input files (crslab/toml_file.py): every bound at its edge (the exact
count passes, one more is refused with one line ``FILE:LINE: KEY: problem``), lines found where
the file sets each key, and any text at all answered by a value or that one line (hypothesis)."""

from __future__ import annotations

import json
import math
import os
import re
import tomllib
import tracemalloc

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from crslab import toml_file
from crslab.toml_file import (
    LARGEST,
    MAX_FILE_BYTES,
    MAX_INTEGER,
    MAX_NESTING,
    SMALLEST,
    TomlFile,
    read_input,
)


class Bad(ValueError):
    pass


def parse(text: str) -> TomlFile:
    return TomlFile.parse(text, "f.toml", Bad)


def refused(text: str) -> str:
    with pytest.raises(Bad) as caught:
        parse(text)
    message = str(caught.value)
    assert "\n" not in message
    return message


# -- numbers ---------------------------------------------------------------------------------------

def test_a_400_digit_integer_is_refused_at_its_line():
    assert refused('name = "x"\n[peg]\nseed = ' + "9" * 400 + "\n") == (
        f"f.toml:3: peg.seed: a whole number of 400 digits is too large (at most {MAX_INTEGER} in size)")


@pytest.mark.parametrize("value, ok", [
    (str(MAX_INTEGER), True), (str(MAX_INTEGER + 1), False),
    (str(-MAX_INTEGER), True), (str(-MAX_INTEGER - 1), False),
    ("0x7fff_ffff_ffff_ffff", True), ("0x8000_0000_0000_0000", False), ("0o" + "7" * 70, False),
    ("9" * 5000, False),  # past Python's own 4300 digits
])
def test_whole_numbers_at_the_edge(value, ok):
    text = f"a = 1\nb = {value}\n"
    if ok:
        assert parse(text).data["b"] == int(value.replace("_", ""), 0)
    else:
        assert refused(text).startswith("f.toml:2: b: ")


@pytest.mark.parametrize("value, problem", [
    ("1e12", None), ("-1e12", None), ("1.0000001e12", "too large"), ("1e300", "too large"),
    ("1e400", "too large"), ("1e-12", None), ("-1e-12", None), ("9.99e-13", "too small"),
    ("1e-300", "too small"), ("1e-400", "too small"), ("0.0", None), ("-0e5", None), ("inf", None),
    ("-inf", None), ("nan", "not a number"), ("+nan", "not a number"), ("3_000.5", None),
])
def test_numbers_with_a_fraction_or_an_exponent_at_the_edge(value, problem):
    text = f"[mass]\nkg = [1, {value}]\n"
    if problem is None:
        got = parse(text).data["mass"]["kg"][1]
        assert got == float(value.replace("_", "")) or (math.isnan(got) and "nan" in value)
    else:
        message = refused(text)
        assert message.startswith(f"f.toml:2: mass.kg: {value} is {problem}"), message


def test_the_bounds_are_the_documented_ones():
    assert (LARGEST, SMALLEST, MAX_INTEGER) == (1e12, 1e-12, 2**63 - 1)
    assert refused("x = 2e12\n") == "f.toml:1: x: 2e12 is too large a number (at most 1e+12 in size)"
    assert refused("x = 2e-13\n") == "f.toml:1: x: 2e-13 is too small a number (at least 1e-12 in size, or 0)"


def test_numbers_inside_strings_and_comments_are_text():
    doc = parse('a = "1e300 [[[[[[[[[[ 9999999999999999999999"  # 1e-300 {{{{{{{{{{\nb = \'nan\'\n')
    assert doc.data == {"a": "1e300 [[[[[[[[[[ 9999999999999999999999", "b": "nan"}


# -- nesting ---------------------------------------------------------------------------------------

def nested_array(depth: int) -> str:
    return "x = " + "[" * depth + "1" + "]" * depth + "\n"


def nested_inline(depth: int) -> str:
    return "x = " + "{a = " * depth + "1" + "}" * depth + "\n"


@pytest.mark.parametrize("make", [nested_array, nested_inline], ids=["arrays", "inline tables"])
def test_nesting_at_the_edge(make):
    assert parse(make(MAX_NESTING)).data["x"] is not None
    key = "x" + (".a" * MAX_NESTING if make is nested_inline else "")
    assert refused(make(MAX_NESTING + 1)) == (f"f.toml:1: {key}: nested too deep (a value sits inside at "
                                              f"most {MAX_NESTING} tables and arrays)")


def test_deep_nesting_never_reaches_the_parser():
    """Python's TOML parser recurses once per level: 100,000 of them is one line, not a RecursionError."""
    assert refused("a = 1\n\nx = " + "[" * 100_000).startswith("f.toml:3: x: nested too deep")
    assert refused("x = " + "{y=" * 100_000).startswith("f.toml:1: x.y.y.y.y.y.y.y.y: nested too deep")


def test_tables_and_dotted_keys_count_as_nesting():
    names = [f"t{i}" for i in range(MAX_NESTING + 1)]
    assert parse(f"[{'.'.join(names[:MAX_NESTING])}]\nv = 1\n")
    header = ".".join(names)
    assert refused(f"[{header}]\nv = 1\n").startswith(f"f.toml:1: {header}: nested too deep")
    assert parse(f"{'.'.join(names)} = 1\n")  # the value inside 8 tables
    deeper = ".".join([*names, "v"])
    assert refused(f"{deeper} = 1\n").startswith("f.toml:1: ")
    # an array of tables is an array and a table: [[e]] then a list of lists inside
    assert parse("[[e]]\nx = [[[[[[1]]]]]]\n")
    assert refused("[[e]]\nx = [[[[[[[1]]]]]]]\n").startswith("f.toml:2: e.x: nested too deep")


# -- the file -------------------------------------------------------------------------------------

def test_a_file_of_the_largest_size_is_read_and_one_byte_more_is_refused(tmp_path):
    path = tmp_path / "big.toml"
    filler = "# " + "x" * 97 + "\n"
    text = 'a = 1\n' + filler * ((MAX_FILE_BYTES - 6) // len(filler))
    text += "#" * (MAX_FILE_BYTES - len(text) - 1) + "\n"
    assert len(text) == MAX_FILE_BYTES
    path.write_text(text)
    assert TomlFile.read(path, "world file", Bad).data == {"a": 1}
    path.write_text(text + " ")
    with pytest.raises(Bad, match=rf"^{re.escape(str(path))}: is larger than a world file may be "
                                  rf"\(1,000,000 bytes at most\)$"):
        TomlFile.read(path, "world file", Bad)


def test_a_huge_file_is_refused_without_being_read(tmp_path):
    """193 MB took 573 MB of memory: now only the limit and one byte are ever read."""
    path = tmp_path / "huge.toml"
    with open(path, "wb") as f:
        f.truncate(193 * 1024 * 1024)
    tracemalloc.start()
    try:
        with pytest.raises(Bad, match="is larger than a scenario file may be"):
            TomlFile.read(path, "scenario file", Bad)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 3 * MAX_FILE_BYTES


def test_what_is_no_file_is_one_line(tmp_path):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    with pytest.raises(Bad, match=r"pipe.toml: is not a file \(a scenario file is a regular file\)$"):
        read_input(fifo, "scenario file", Bad)  # a FIFO is never waited on
    with pytest.raises(Bad, match=r": is a folder \(a plant file is a regular file\)$"):
        read_input(tmp_path, "plant file", Bad)
    with pytest.raises(Bad, match=r"nothing.toml: no such robot file$"):
        read_input(tmp_path / "nothing.toml", "robot file", Bad)
    text = tmp_path / "latin1.toml"
    text.write_bytes(b'a = 1\nname = "caf\xe9"\n')
    with pytest.raises(Bad, match=r"latin1.toml:2: not UTF-8 text \(byte 0xe9\)$"):
        TomlFile.read(text, "world file", Bad)
    with pytest.raises(Bad, match=r"^shown:3: not valid TOML: "):
        TomlFile.parse("a = 1\n\nb = = 2\n", "shown", Bad)


# -- lines ------------------------------------------------------------------------------------------

TRICKY = '''\
# a comment with [brackets] and key = "value"
title = """
[not_a_table]
x = 1
"""
"dotted.key" = 2
a.b = 3
literal = \'\'\'it's ]] fine\'\'\'
[tables."with.dots"]
inner = { k = 1, l = [1,
  2] }
[[event]]
at = 1
[[event]]
# between
at = 2
kind = "estop"
[[event.sub]]
v = 4
'''


def test_lines_are_where_the_file_sets_each_key():
    doc = parse(TRICKY)
    assert doc.data == tomllib.loads(TRICKY)
    assert doc.line_of(("title",)) == 2 and doc.line_of(("dotted.key",)) == 6
    assert doc.line_of(("a", "b")) == 7 and doc.line_of(("literal",)) == 8
    assert doc.line_of(("tables", "with.dots")) == 9
    assert doc.line_of(("tables", "with.dots", "inner", "l", 1)) == 11
    assert doc.line_of(("event", 0, "at")) == 13 and doc.line_of(("event", 1, "at")) == 16
    assert doc.line_of(("event", 1, "missing")) == 14  # a missing key: its table's header
    assert doc.line_of(("event", 1, "sub", 0, "v")) == 19
    assert doc.line_of(("nothing",)) is None
    event = doc.tables("event")[1]
    assert str(event.fail("kind", "unknown")) == "f.toml:17: kind: unknown"
    assert str(doc.table(("tables", "with.dots"), "t").fail("inner", "x")) == "f.toml:10: t.inner: x"


def test_each_value_is_read_with_its_type_and_range():
    doc = parse('[peg]\nmass_kg = 0.03\nsize = [1, 2, "3"]\nn = 2.5\nname = 3\nok = true\n'
                'pts = [[0, 0], [1, 2]]\nbig = [1, inf, 3]\n')
    peg = doc.table(("peg",), "peg")
    assert peg.number("mass_kg", minimum=0.001, maximum=1.0) == 0.03
    cases = [
        (lambda: peg.number("mass_kg", maximum=0.01),
         "f.toml:2: peg.mass_kg: must be at most 0.01, got 0.03"),
        (lambda: peg.number("mass_kg", minimum=0.05),
         "f.toml:2: peg.mass_kg: must be at least 0.05, got 0.03"),
        (lambda: peg.numbers("size", 3), "f.toml:3: peg.size: must be a list of 3 numbers, got [1, 2, '3']"),
        (lambda: peg.integer("n"), "f.toml:4: peg.n: must be a whole number, got 2.5"),
        (lambda: peg.text("name"), "f.toml:5: peg.name: must be a string, got 3"),
        (lambda: peg.boolean("name"), "f.toml:5: peg.name: must be true or false, got 3"),
        (lambda: peg.numbers("big", 3), "f.toml:8: peg.big: must be a list of 3 numbers, got [1, inf, 3]"),
        (lambda: peg.number("gone"), "f.toml:1: peg.gone: missing"),
        (lambda: peg.check_keys(["mass_kg"]), "f.toml:3: peg.size: unknown key (allowed: mass_kg)"),
        (lambda: doc.table(("peg", "ok")), "f.toml:6: peg.ok: must be a table ([peg.ok])"),
    ]
    for call, message in cases:
        with pytest.raises(Bad) as caught:
            call()
        assert str(caught.value) == message
    assert peg.points("pts", 2) == ((0.0, 0.0), (1.0, 2.0)) and peg.boolean("ok") is True
    assert peg.number("gone", default=4.0) == 4.0


def test_an_error_quotes_a_long_value_cut():
    doc = parse("x = [" + ", ".join(["1"] * 10_000) + "]\n")
    with pytest.raises(Bad) as caught:
        doc.table().text("x")
    assert len(str(caught.value)) < 150 and str(caught.value).endswith("(30000 characters)")


# -- any text ----------------------------------------------------------------------------------------

KEYS = st.one_of(st.from_regex(r"[A-Za-z0-9_-]{1,6}", fullmatch=True),
                 st.text(alphabet='ab.#[]"\'\\= {}\n', max_size=6))
SCALARS = st.one_of(st.integers(-2**70, 2**70), st.floats(width=64), st.booleans(),
                    st.text(alphabet='ab"\'\\#[]{}\n=,. ', max_size=8))
VALUES = st.recursive(SCALARS, lambda inner: st.one_of(st.lists(inner, max_size=3),
                                                       st.dictionaries(KEYS, inner, max_size=3)),
                      max_leaves=30)


def key_text(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)


def value_text(value: object, multiline: bool) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") if math.isinf(value) \
            else repr(value)
    if isinstance(value, str):
        if multiline and '"""' not in value and not value.endswith('"') and "\\" not in value:
            return f'"""{value}"""'
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + (",\n" if multiline else ", ").join(value_text(v, multiline) for v in value) + "]"
    assert isinstance(value, dict)
    return "{" + ", ".join(f"{key_text(k)} = {value_text(v, False)}" for k, v in value.items()) + "}"


def containers(value: object) -> int:
    """How many tables and arrays the deepest value of ``value`` sits inside (a container counts)."""
    if isinstance(value, list):
        return 1 + max(map(containers, value), default=0)
    if isinstance(value, dict):
        return 1 + max(map(containers, value.values()), default=0)
    return 0


def largest_problem(value: object) -> bool:
    """Whether ``value`` holds a number the reader refuses."""
    if isinstance(value, list):
        return any(map(largest_problem, value))
    if isinstance(value, dict):
        return any(map(largest_problem, value.values()))
    if isinstance(value, bool):
        return False
    if isinstance(value, int):
        return abs(value) > MAX_INTEGER
    if isinstance(value, float):
        inside = value == 0 or SMALLEST <= abs(value) <= LARGEST
        return math.isnan(value) or (math.isfinite(value) and not inside)
    return False


@settings(max_examples=150, suppress_health_check=list(HealthCheck), deadline=None)
@given(st.dictionaries(KEYS, VALUES, max_size=4), st.booleans())
def test_a_generated_file_reads_as_tomllib_reads_it_within_the_bounds(top, multiline):
    text, lines = "", {}
    for key, value in top.items():
        lines[key] = text.count("\n") + 1
        text += f"{key_text(key)} = {value_text(value, multiline)}  # [ {{ \"\n"
    try:
        expected = tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        return
    except RecursionError:
        expected = None
    try:
        doc = parse(text)
    except Bad as exc:
        assert expected is None or containers(expected) - 1 > MAX_NESTING or largest_problem(expected), exc
        return
    assert expected is not None and doc.data == expected or (doc.data != doc.data)  # nan never passes
    assert containers(expected) - 1 <= MAX_NESTING and not largest_problem(expected)
    for key in top:
        assert doc.line_of((key,)) == lines[key]


@settings(max_examples=500, suppress_health_check=list(HealthCheck), deadline=None)
@given(st.text(alphabet='ab1e.-+_"\'\\#[]{}\n=, x0', max_size=80))
def test_any_text_is_values_or_one_line(text):
    try:
        parse(text)
    except Bad as exc:
        assert str(exc).startswith("f.toml") and "\n" not in str(exc).split(": not valid TOML")[0]


def test_read_toml_is_the_checked_reader(tmp_path):
    path = tmp_path / "robot.toml"
    path.write_text("[links]\nmass = 1e300\n")
    with pytest.raises(Bad, match=rf"^{re.escape(str(path))}:2: links.mass: 1e300 is too large"):
        toml_file.read_toml(path, "robot file", Bad)
