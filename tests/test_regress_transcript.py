"""Golden files and transcript lines: the header round trip, line ends, ticks of lines."""

import pytest

from crslab.regress.transcript import (
    GOLDEN_MAX_BYTES,
    GoldenError,
    read_golden,
    recorded_run,
    split_lines,
    write_golden,
)


def test_line_ends_of_both_generations_and_a_partial_last_line():
    lines = split_lines(b"a\n\rb\r\nc\nd\re")
    assert [x.text for x in lines] == ["a", "b", "c", "d", "e"]
    assert split_lines(b"") == [] and [x.text for x in split_lines(b"\n\r\n\r")] == ["", ""]


def test_every_line_gets_the_tick_of_the_call_that_printed_its_first_byte():
    calls = [(4100, b"0.00 "), (4100, b"1.00\n\r"), (4600, b"2.00\n\r3.00\n\r"), (5100, b"4.0"),
             (5101, b"0\n\r")]
    lines = split_lines(b"".join(d for _, d in calls), calls)
    assert [(x.number, x.text, x.tick) for x in lines] == [
        (1, "0.00 1.00", 4100), (2, "2.00", 4600), (3, "3.00", 4600), (4, "4.00", 5100)]
    assert lines[1].time == "t = 4.600 s"


def test_golden_header_round_trip_keeps_the_exact_bytes(tmp_path):
    body = b"0.00 -24.06 13.75\n\r# not a header line\n\r\xff\n\r"
    path = tmp_path / "g.txt"
    write_golden(path, {"crslab": "0.1.0", "scenario": "tour", "end_s": "25.000"}, body)
    golden = read_golden(path)
    assert golden.header == {"crslab": "0.1.0", "scenario": "tour", "end_s": "25.000"}
    assert golden.body == body
    assert path.read_bytes().startswith(b"# crslab transcript")


def test_a_plain_transcript_is_a_golden_file_too(tmp_path):
    path = tmp_path / "t.txt"
    path.write_bytes(b"# 1.00\n\r")
    assert read_golden(path).header == {} and read_golden(path).body == b"# 1.00\n\r"


def test_bad_golden_files_name_the_file_and_line(tmp_path):
    with pytest.raises(GoldenError, match=r"nowhere.txt: no such golden file"):
        read_golden(tmp_path / "nowhere.txt")
    path = tmp_path / "g.txt"
    path.write_bytes(b"# crslab transcript\n# scenario: tour\n1.00\n\r")
    with pytest.raises(GoldenError, match=r"g.txt: the crslab header has no end line"):
        read_golden(path)
    path.write_bytes(b"# crslab transcript\n# scenario: tour\nbroken\n# ----\n1.00\n\r")
    with pytest.raises(GoldenError, match=r"g.txt:3: header line must read '# key: value', got 'broken'"):
        read_golden(path)


@pytest.mark.parametrize("field, value, problem", [
    ("end_s", "1e300", "must be a number of seconds above 0, at most 86400, got '1e300'"),
    ("end_s", "86400.5", "must be a number of seconds above 0, at most 86400, got '86400.5'"),
    ("end_s", "9" * 400, "must be a number of seconds above 0, at most 86400, got '9999999999"),
    ("end_s", "nan", "must be a number of seconds above 0, at most 86400, got 'nan'"),
    ("rest_motor_rad", "0 -0.42 1e-300x", "must be three angles within +-pi rad, got '0 -0.42 1e-300x'"),
    ("rest_motor_rad", "0 -0.42 inf", "must be three angles within +-pi rad, got '0 -0.42 inf'"),
    ("rest_motor_rad", "0 -0.42 3.2", "must be three angles within +-pi rad, got '0 -0.42 3.2'"),
    ("startup_delay", "maybe", "must be yes or no, got 'maybe'"),
])
def test_each_header_field_is_checked_and_named_with_its_line(tmp_path, field, value, problem):
    path = tmp_path / "g.txt"
    fields = {"scenario": "tour", "end_s": "6.000", "rest_motor_rad": "0 -0.42 0.24", "startup_delay": "no"}
    write_golden(path, {**fields, field: value}, b"1.00\n\r")
    line = 2 + list(fields).index(field)
    with pytest.raises(GoldenError) as caught:
        recorded_run(read_golden(path))
    assert str(caught.value).startswith(f"{path}:{line}: {field}: {problem}")
    assert len(str(caught.value)) < len(f"{path}") + 200
    fine = {"end_s": "86400", "rest_motor_rad": "0 -0.42 3.14", "startup_delay": "yes"}.get(field)
    write_golden(path, {**fields, field: fine}, b"1.00\n\r")
    recorded_run(read_golden(path))  # the edge itself is a run


def test_a_golden_file_past_its_size_is_refused_unread(tmp_path):
    path = tmp_path / "huge.txt"
    with open(path, "wb") as f:
        f.write(b"# crslab transcript: x\n# ----\n")
        f.truncate(GOLDEN_MAX_BYTES + 1)
    with pytest.raises(GoldenError, match=rf"huge.txt: is larger than a golden file may be "
                                          rf"\({GOLDEN_MAX_BYTES:,} "):
        read_golden(path)
    with open(path, "r+b") as f:
        f.truncate(GOLDEN_MAX_BYTES)
    assert len(read_golden(path).body) == GOLDEN_MAX_BYTES - len(b"# crslab transcript: x\n# ----\n")
