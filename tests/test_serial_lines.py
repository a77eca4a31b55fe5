"""One rule cuts the board's serial bytes into lines (crslab/serial_lines.py): the golden compare's
split, a run's result, and the rerun log's streaming cut agree on every line end, a lone ``\\r``
included, however the bytes are split into serial_printf calls."""

from hypothesis import given
from hypothesis import strategies as st

from crslab.regress.transcript import split_lines
from crslab.run.status import RunResult, RunStatus
from crslab.serial_lines import SerialLines, split

ENDS = [b"\n\r", b"\r\n", b"\n", b"\r"]


def streamed(calls: list[bytes]) -> list[str]:
    lines = SerialLines()
    out = [text for i, call in enumerate(calls) for _, text in lines.feed(i, call)]
    return out + [text for _, text in lines.finish()]


def test_each_line_end_ends_one_line_and_a_lone_cr_is_one():
    data = b"a\n\rb\r\nc\nd\re\r\rf\n\ng"
    expected = ["a", "b", "c", "d", "e", "", "f", "", "g"]
    assert [text for _, text in split(data)] == expected
    assert [line.text for line in split_lines(data)] == expected
    assert RunResult(RunStatus.OK, calls=[(0, data)]).lines() == expected
    assert streamed([data]) == expected


def test_a_line_end_split_over_two_calls_is_one_line_end():
    assert streamed([b"a\n", b"\rb\r", b"\nc\n", b"\nd"]) == ["a", "b", "c", "", "d"]
    assert streamed([b"a\r", b"", b"\nb"]) == ["a", "b"]  # an empty call changes nothing


@given(st.lists(st.one_of(st.sampled_from(ENDS), st.binary(max_size=4)), max_size=12), st.data())
def test_streaming_in_any_chunks_gives_the_lines_of_the_whole(pieces, data):
    whole = b"".join(pieces)
    cuts = sorted(data.draw(st.lists(st.integers(0, len(whole)), max_size=6)))
    calls = [whole[a:b] for a, b in zip([0, *cuts], [*cuts, len(whole)])]
    assert streamed(calls) == [text for _, text in split(whole)]
    assert [line.text for line in split_lines(whole, [(0, c) for c in calls])] == streamed(calls)
