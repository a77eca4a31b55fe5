"""The number-aware transcript comparison: tolerance edge cases, text, missing and extra lines."""

import math

from hypothesis import given
from hypothesis import strategies as st

from crslab.regress.compare import compare, compare_lines, numbers_match, tokens
from crslab.regress.transcript import Line


def ok(expected, got, **tol):
    return compare_lines([expected], [got], **tol).ok


def reason(expected, got, **tol):
    return compare_lines([expected], [got], **tol).diffs[0].reason


def test_minus_zero_matches_zero():
    assert ok("0.00 -0.00 13.75", "-0.00 0.00 13.75")
    assert ok("-0.00", "0.00", abs_tol=0.0)  # equal numbers, not a tolerance question
    assert ok("-0", "0", abs_tol=0.0)


def test_a_last_digit_rounding_difference_passes_and_two_digits_do_not():
    assert ok("1.23 -24.06 100000.01", "1.24 -24.07 100000.02")
    assert not ok("1.23", "1.25")
    assert reason("1.23", "1.25") == "number 1 is 1.25, expected 1.23 (off by 0.02)"
    assert not ok("1.23", "1.24", abs_tol=0.0)
    assert ok("1.234567", "1.234568", abs_tol=1e-6)


def test_relative_tolerance():
    assert ok("1000.0", "1001.0", rel_tol=0.001)
    assert not ok("1000.0", "1002.0", rel_tol=0.001)


def test_the_relative_tolerance_scales_by_the_larger_number_and_the_larger_tolerance_wins():
    # 1050 against 950 is off by 100: 0.1 of the larger (105) allows it, 0.1 of the smaller (95)
    # would not, whichever side is the golden's; 0.09 of the larger (94.5) does not
    assert ok("1050", "950", rel_tol=0.1) and ok("950", "1050", rel_tol=0.1)
    assert not ok("1050", "950", rel_tol=0.09) and not ok("950", "1050", rel_tol=0.09)
    assert numbers_match(-1050.0, -950.0, 0.0, 0.1) and not numbers_match(-1050.0, -950.0, 0.0, 0.09)
    # the tolerances do not add up: off by 1.2 is beyond both 0.5 and 0.01 x 101.2
    assert not ok("100", "101.2", abs_tol=0.5, rel_tol=0.01)
    assert ok("100", "101.2", abs_tol=1.2, rel_tol=0.01) and ok("100", "101.2", abs_tol=0.5, rel_tol=0.012)


@given(st.floats(min_value=-1e4, max_value=1e4, allow_nan=False), st.sampled_from([-1, 1]))
def test_any_percent_2f_value_matches_its_neighbour_in_the_last_digit(x, step):
    printed = f"{x:.2f}"
    neighbour = f"{float(printed) + step * 0.01:.2f}"
    assert ok(printed, neighbour)
    assert not ok(printed, f"{float(printed) + step * 0.02:.2f}")


def test_integers_and_flags_must_be_exact_within_the_default():
    assert not ok("error 1 at 2.097 rad", "error 0 at 2.097 rad")
    assert not ok("count 100", "count 101")


def test_a_number_where_text_is_expected_and_the_reverse():
    assert reason("IK: no solution", "1.00 2.00 3.00") == (
        "token 1 is the number 1.00, expected the text 'IK:'; token 2 is the number 2.00, expected the text "
        "'no'; token 3 is the number 3.00, expected the text 'solution'")
    assert reason("1.00 2.00 3.00", "IK: no solution").startswith(
        "token 1 is the text 'IK:', expected the number 1.00")
    assert reason("x 5", "x five") == "token 2 is the text 'five', expected the number 5"


def test_other_text_must_match_exactly_but_blanks_only_separate():
    assert ok("  1.00   2.00", "1.00 2.00")            # %6.2f padding
    assert ok("x=1.00,y=2.00", "x=1.001,y=2.00")
    assert not ok("I love robotics", "I love Robotics")
    assert reason("tau1 = 5", "tau2 = 5") == "token 1 is 'tau2', expected 'tau1'"  # tau1 is a word
    assert reason("1.00 2.00", "1.00 2.00 3.00") == "3 tokens, expected 2"


def test_nan_and_infinity():
    assert ok("nan -inf", "-nan -inf")
    assert not ok("inf", "-inf")
    assert not ok("nan", "0.00")
    assert reason("1.00", "nan") == "number 1 is nan, expected 1.00 (not a finite difference)"
    assert [t.value for t in tokens("information nano")] == [None, None]


def test_lines_missing_or_extra():
    c = compare_lines(["a 1", "b 2", "c 3"], ["a 1"])
    assert [(d.number, d.reason) for d in c.diffs] == [(2, "missing: the run printed only 1 lines"),
                                                       (3, "missing: the run printed only 1 lines")]
    c = compare_lines(["a 1"], ["a 1", "b 2"])
    assert [(d.number, d.reason, d.got.text) for d in c.diffs] == [(2, "extra line: the golden has only 1",
                                                                    "b 2")]
    assert compare_lines([], []).ok


def test_the_report_names_the_first_lines_their_time_and_numbers():
    expected = [Line(1, "0.00 -24.06 13.75"), Line(2, "5.64 0.00 16.75"), Line(3, "0.00 -24.06 13.75")]
    got = [Line(n, text, 4100) for n, text in ((1, "0.00 -24.06 13.75"), (2, "5.64 0.00 16.75"),
                                                (3, "0.00 24.06 13.75"))]
    c = compare(expected, got)
    assert c.diffs[0].numbers == ((2, "-24.06", "24.06"),)
    assert c.report().splitlines() == [
        "mismatch: 1 of 3 lines differ; first at line 3 (t = 4.100 s): number 2 is 24.06, expected -24.06 "
        "(off by 48.12)",
        "line 3 at t = 4.100 s: number 2 is 24.06, expected -24.06 (off by 48.12)",
        "  expected: 0.00 -24.06 13.75",
        "  got:      0.00 24.06 13.75",
    ]
    many = compare([Line(i, "1") for i in range(1, 9)], [Line(i, "2", 1000 * i) for i in range(1, 9)])
    report = many.report(max_lines=2).splitlines()
    assert report[-1] == "... and 6 more differing lines" and len(report) == 1 + 2 * 3 + 1


def test_numbers_match_is_symmetric_and_exact_at_zero_tolerance():
    assert numbers_match(2.5, 2.5, 0.0, 0.0)
    assert not numbers_match(2.5, 2.5000001, 0.0, 0.0)
    assert numbers_match(math.inf, math.inf, 0.0, 0.0)
