"""JUnit XML reports, the format CI systems (GitHub Actions, GitLab, Jenkins) display.

>>> xml = junit_xml("crslab check", [Case("lab1.c on tour", "crslab.check", 0.5, "failure",
...                  "mismatch: 1 of 3 lines differ", "line 2 ...")])
>>> print(xml.decode().splitlines()[1])
<testsuites name="crslab check" tests="1" failures="1" errors="0" time="0.500">
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from crslab.output_paths import with_parent
from crslab.untrusted_text import for_xml as _clean


@dataclass(frozen=True)
class Case:
    """One test case: ``status`` is pass, failure (a mismatch) or error (the lab did not build or
    run); ``message`` is one line, ``details`` the full report."""

    name: str
    classname: str
    time_s: float
    status: str = "pass"
    message: str = ""
    details: str = ""


def junit_xml(suite: str, cases: Sequence[Case]) -> bytes:
    """A JUnit XML document with one test suite holding ``cases``."""
    failures = sum(c.status == "failure" for c in cases)
    errors = sum(c.status == "error" for c in cases)
    total = f"{sum(c.time_s for c in cases):.3f}"
    root = ET.Element("testsuites", name=suite, tests=str(len(cases)), failures=str(failures),
                      errors=str(errors), time=total)
    node = ET.SubElement(root, "testsuite", name=suite, tests=str(len(cases)), failures=str(failures),
                         errors=str(errors), time=total)
    for c in cases:
        case = ET.SubElement(node, "testcase", name=_clean(c.name), classname=_clean(c.classname),
                             time=f"{c.time_s:.3f}")
        if c.status in ("failure", "error"):
            child = ET.SubElement(case, c.status, message=_clean(c.message), type=c.status)
            child.text = _clean(c.details or c.message)
    ET.indent(root)
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8") + b"\n"


def write_junit(path: Path, suite: str, cases: Sequence[Case]) -> None:
    """Write :func:`junit_xml` to ``path``."""
    with_parent(path).write_bytes(junit_xml(suite, cases))
