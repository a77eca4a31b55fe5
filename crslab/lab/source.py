"""A lab file's text, carried to wherever it runs (another process, another machine), and built
there from a private copy alone in a folder of its own: in the sandbox it can then read nothing
but itself, and it never needs the folder it came from. Builds are cached by content on each
machine (:func:`crslab.lab.build.build_lab`), so a worker builds a lab once.

>>> src = LabSource("mylab.c", b"void lab(void) {}")
>>> with src.private_build(sandboxed=False) as build:
...     build.source.name, build.source.read_bytes() == src.text
('mylab.c', True)
"""

from __future__ import annotations

import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from crslab.lab.build import LabBuild, build_lab
from crslab.lab.lab_file import read_lab_file


@dataclass(frozen=True)
class LabSource:
    """A lab file's name (what messages call it) and its bytes."""

    name: str
    text: bytes

    @classmethod
    def read(cls, path: Path) -> LabSource:
        """The lab file at ``path``; a missing or unreadable one is a :class:`LabBuildError`."""
        return cls(path.name, read_lab_file(path))

    @contextmanager
    def private_build(self, *, native: bool = False, sanitize: bool = False,
                      sandboxed: bool = True) -> Iterator[LabBuild]:
        """Write the text into a fresh folder of its own and build it there; the folder is removed
        when the block ends. Raises what :func:`build_lab` raises."""
        with tempfile.TemporaryDirectory(prefix="crslab-lab-") as folder:
            copy = Path(folder) / self.name
            copy.write_bytes(self.text)
            yield build_lab(copy, native=native, sanitize=sanitize, sandboxed=sandboxed)
