"""Text a submission controls (a path its lab tried to open, what it printed, its file's name, the
compiler's quotes of its source), made safe for where it goes: a terminal, a text report, a CSV
cell, an XML document. No control character, escape sequence, bidirectional override or
non-character reaches any of them raw; each is shown as a visible escape instead (``\\x1b``,
``\\u202e``), so a report never says what its bytes do not show, and a CSV cell never starts a
formula.

>>> for_terminal("ok\\x1b[32m pass\\x1b[0m")
'ok\\\\x1b[32m pass\\\\x1b[0m'
>>> for_terminal("evil\\u202etxt.c")
'evil\\\\u202etxt.c'
>>> for_text("line 1\\nline\\x07 2")
'line 1\\nline\\\\x07 2'
>>> for_csv("=HYPERLINK(\\"http://x\\")")
'\\'=HYPERLINK("http://x")'
>>> for_xml("a\\ufffeb\\x01")
'a\\\\ufffeb\\\\x01'
"""

from __future__ import annotations

import unicodedata

_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def _unsafe(ch: str, keep_newlines: bool) -> bool:
    code = ord(ch)
    if ch == "\n" and keep_newlines:
        return False
    if ch == "\t":
        return False
    if code < 0x20 or 0x7F <= code <= 0x9F:  # C0 and C1 controls, DEL: escape sequences start here
        return True
    if 0xD800 <= code <= 0xDFFF or 0xFDD0 <= code <= 0xFDEF or (code & 0xFFFE) == 0xFFFE:
        return True  # surrogates (from undecodable bytes) and non-characters
    return unicodedata.category(ch) in ("Cf", "Zl", "Zp")  # bidi overrides, zero-width, separators


def _escape(ch: str) -> str:
    code = ord(ch)
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


def _escaped(text: str, keep_newlines: bool) -> str:
    return "".join(_escape(ch) if _unsafe(ch, keep_newlines) else ch for ch in text)


def for_terminal(text: str) -> str:
    """One line for a terminal: every control character (newlines too) escaped."""
    return _escaped(text, keep_newlines=False)


def for_text(text: str) -> str:
    """Lines for a text file or a terminal: newlines kept, every other control escaped."""
    return _escaped(text.replace("\r\n", "\n"), keep_newlines=True)


def for_csv(text: str) -> str:
    """A CSV cell: one line, and never the start of a formula (OWASP's advice: a leading quote)."""
    cell = for_terminal(text)
    return "'" + cell if cell.startswith(_FORMULA_START) else cell


def for_xml(text: str) -> str:
    """Text XML 1.0 can hold, every control but newlines and tabs escaped (ElementTree escapes
    the markup characters)."""
    return _escaped(text, keep_newlines=True)
