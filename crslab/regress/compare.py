"""Compare two transcripts line by line, number-aware.

Each line is split into tokens: numbers (``-0.00``, ``12``, ``1.5e-3``, ``nan``, ``-inf``; a
number glued to a word before it, as in ``tau1``, is part of that word) and the words between
them (runs of other non-blank characters). Blanks only separate tokens, so ``%6.2f`` padding
never matters. Two numbers match when they differ by at most ``max(abs_tol, rel_tol * |larger|)``
(NaN matches NaN, an infinity only itself); everything else must be equal exactly. Lines are
paired by position: the golden's line 7 with the run's line 7.

>>> c = compare_lines(["1.00 -0.00 x"], ["1.01  0.00 x"])
>>> c.ok
True
>>> c = compare_lines(["10.00 0.00 20.00"], ["10.00 0.00 -20.00"])
>>> print(c.diffs[0].reason)
number 3 is -20.00, expected 20.00 (off by 40)
"""

from __future__ import annotations

import math
import re
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field

from crslab.regress.transcript import Line

DEFAULT_ABS_TOL = 0.01
"""One unit in the last digit of ``%.2f``, the course's usual format."""
DEFAULT_REL_TOL = 0.0
_SLACK = 8 * sys.float_info.epsilon  # decimal numbers are not exact in binary: 1.24 - 1.23 > 0.01

_NUMBER = re.compile(
    r"(?<![\w.])[-+]?(?:(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?|(?:nan|inf(?:inity)?)(?![\w]))",
    re.IGNORECASE)


@dataclass(frozen=True)
class Token:
    """A number (``value`` set) or a word (``value`` None), as printed."""

    text: str
    value: float | None = None

    @property
    def is_number(self) -> bool:
        """True for a number."""
        return self.value is not None


def tokens(line: str) -> list[Token]:
    """The tokens of one printed line.

    >>> [(t.text, t.value) for t in tokens("x=1.50, tau1 -nan")]
    [('x=', None), ('1.50', 1.5), (',', None), ('tau1', None), ('-nan', nan)]
    """
    out: list[Token] = []

    def words(text: str) -> None:
        out.extend(Token(w) for w in text.split())

    pos = 0
    for m in _NUMBER.finditer(line):
        words(line[pos:m.start()])
        out.append(Token(m.group(0), float(m.group(0))))
        pos = m.end()
    words(line[pos:])
    return out


def numbers_match(expected: float, got: float, abs_tol: float, rel_tol: float) -> bool:
    """Whether two printed numbers are the same within the tolerances.

    >>> numbers_match(1.23, 1.24, 0.01, 0.0), numbers_match(1.23, 1.25, 0.01, 0.0)
    (True, False)
    >>> numbers_match(-0.0, 0.0, 0.0, 0.0), numbers_match(float("nan"), float("nan"), 0.01, 0.0)
    (True, True)
    """
    if math.isnan(expected) or math.isnan(got):
        return math.isnan(expected) and math.isnan(got)
    if math.isinf(expected) or math.isinf(got):
        return expected == got
    scale = max(abs(expected), abs(got))
    return abs(expected - got) <= max(abs_tol, rel_tol * scale) + _SLACK * scale


def _off_by(expected: float, got: float) -> str:
    diff = abs(expected - got)
    return f"off by {diff:.6g}" if math.isfinite(diff) else "not a finite difference"


@dataclass(frozen=True)
class LineDiff:
    """One line that differs: the golden's and the run's line (None when missing) and why."""

    number: int
    expected: Line | None
    got: Line | None
    reason: str
    numbers: tuple[tuple[int, str, str], ...] = ()  # (1-based token number, expected, got)


def compare_line(expected: str, got: str, abs_tol: float, rel_tol: float) -> tuple[str, tuple] | None:
    """Why line ``got`` does not match ``expected`` (and the numbers that differ), or None."""
    e_tokens, g_tokens = tokens(expected), tokens(got)
    reasons: list[str] = []
    numbers = []
    for i, (e, g) in enumerate(zip(e_tokens, g_tokens), start=1):
        if e.is_number and g.is_number:
            if not numbers_match(e.value, g.value, abs_tol, rel_tol):  # type: ignore[arg-type]
                numbers.append((i, e.text, g.text))
                reasons.append(f"number {i} is {g.text}, expected {e.text} ({_off_by(e.value, g.value)})")
        elif e.is_number:
            reasons.append(f"token {i} is the text {g.text!r}, expected the number {e.text}")
        elif g.is_number:
            reasons.append(f"token {i} is the number {g.text}, expected the text {e.text!r}")
        elif e.text != g.text:
            reasons.append(f"token {i} is {g.text!r}, expected {e.text!r}")
    if len(e_tokens) != len(g_tokens):
        reasons.append(f"{len(g_tokens)} tokens, expected {len(e_tokens)}")
    if not reasons:
        return None
    return "; ".join(reasons), tuple(numbers)


@dataclass
class Comparison:
    """The result of comparing a run's lines with the golden's."""

    expected_count: int
    got_count: int
    diffs: list[LineDiff] = field(default_factory=list)
    abs_tol: float = DEFAULT_ABS_TOL
    rel_tol: float = DEFAULT_REL_TOL

    @property
    def ok(self) -> bool:
        """True when every line matches and none is missing or extra."""
        return not self.diffs

    def headline(self) -> str:
        """One line: match, or how many lines differ and where the first is."""
        if self.ok:
            return f"match: {self.got_count} lines within abs tol {self.abs_tol:g}, rel tol {self.rel_tol:g}"
        first = self.diffs[0]
        when = f" ({first.got.time})" if first.got is not None and first.got.tick is not None else ""
        return (f"mismatch: {len(self.diffs)} of {max(self.expected_count, self.got_count)} lines differ; "
                f"first at line {first.number}{when}: {first.reason}")

    def report(self, max_lines: int = 5) -> str:
        """The headline and the first ``max_lines`` differing lines, each with its simulated time,
        the numbers that differ and both texts."""
        out = [self.headline()]
        if self.ok:
            return out[0]
        for d in self.diffs[:max_lines]:
            when = f" at {d.got.time}" if d.got is not None and d.got.tick is not None else ""
            out.append(f"line {d.number}{when}: {d.reason}")
            out.append(f"  expected: {d.expected.text if d.expected is not None else '(nothing)'}")
            out.append(f"  got:      {d.got.text if d.got is not None else '(nothing)'}")
        if len(self.diffs) > max_lines:
            out.append(f"... and {len(self.diffs) - max_lines} more differing lines")
        return "\n".join(out)


def compare(expected: Sequence[Line], got: Sequence[Line], *, abs_tol: float = DEFAULT_ABS_TOL,
            rel_tol: float = DEFAULT_REL_TOL) -> Comparison:
    """Compare a run's lines (``got``) with the golden's (``expected``), line by line."""
    result = Comparison(len(expected), len(got), abs_tol=abs_tol, rel_tol=rel_tol)
    for i in range(max(len(expected), len(got))):
        e = expected[i] if i < len(expected) else None
        g = got[i] if i < len(got) else None
        if e is None:
            result.diffs.append(LineDiff(i + 1, None, g, f"extra line: the golden has only {len(expected)}"))
        elif g is None:
            last = got[-1].time if got and got[-1].tick is not None else ""
            after = f" (its last line was at {last})" if last else ""
            result.diffs.append(LineDiff(i + 1, e, None,
                                         f"missing: the run printed only {len(got)} lines{after}"))
        else:
            why = compare_line(e.text, g.text, abs_tol, rel_tol)
            if why is not None:
                result.diffs.append(LineDiff(i + 1, e, g, why[0], why[1]))
    return result


def compare_lines(expected: Sequence[str], got: Sequence[str], **tolerances: float) -> Comparison:
    """:func:`compare` on plain strings (no ticks)."""
    return compare([Line(i + 1, t) for i, t in enumerate(expected)],
                   [Line(i + 1, t) for i, t in enumerate(got)], **tolerances)
