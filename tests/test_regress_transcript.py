"""Golden files and transcript lines: the header round trip, line ends, ticks of lines."""

import pytest

from crslab.regress.transcript import GoldenError, read_golden, split_lines, write_golden


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
