"""What the page may read of the server's messages: files named as the user gave them, never a
server path.

Every message a session sends the page (a compiler's diagnostics, a run's one-line diagnosis, a
scenario's or a golden file's error, a check's report) passes :meth:`PageText.message`: the
session's own folders are taken off the names of the files the page sent (``lab.c`` stays
``lab.c``), and any other absolute path (the build cache, crslab's install, the compiler's headers,
a temporary folder) is cut to its last part (``stdio.h``), so a page learns nothing of the
server's layout. Only chunks (the lab's own printed bytes and numbers) pass untouched.

>>> page = PageText(Path("/tmp/crslab-serve-a1b2"), roots=[Path("/home/ta one/.cache/crslab")])
>>> page.text("/tmp/crslab-serve-a1b2/lab/divide by zero.c:9:3: error: x")
'divide by zero.c:9:3: error: x'
>>> page.text("In file included from /home/ta one/.cache/crslab/zig/lib/libc/include/stdio.h:12:")
'In file included from stdio.h:12:'
>>> page.text("'/usr/lib/python3/dist-packages/crslab/include/F28335Serial.h' not found; 1/2 N/m")
"'F28335Serial.h' not found; 1/2 N/m"
>>> page.text("cannot open ~/.cache/crslab/x.toml (No such file)")
'cannot open x.toml (No such file)'
"""

from __future__ import annotations

import json
import os
import re
import sys
import tempfile
from collections.abc import Iterable
from pathlib import Path

SESSION_SUBFOLDERS = ("lab", "scenario", "golden", "out")
"""The session folder's parts that hold the page's own files (:mod:`crslab.serve.page_process`)."""
CHUNK = b'{"type": "chunk"'
"""How a chunk's message starts (:func:`crslab.sinks.page_stream.message`): passed untouched."""
_PATH = re.compile(r"""(?<![\w.~/-])~?/(?:[^\s/'"`()<>,;:\[\]{}]+/)*([^\s/'"`()<>,;:\[\]{}]+)""")
"""An absolute path (or ``~/...``), its last part in group 1: stops at a space, a quote, a colon
(``file.c:9:3``) or a bracket; a slash inside a word (``N/m``, ``1/2``) does not start one."""


def server_roots() -> list[Path]:
    """Folders whose names may hold spaces and that messages quote: the home, the build cache,
    the temporary folder, Python's prefix and crslab's install."""
    import crslab
    from crslab.cache import cache_dir

    roots = [Path.home(), Path(tempfile.gettempdir()), Path(sys.prefix), Path(crslab.__file__).parent.parent]
    try:
        roots.append(cache_dir())
    except OSError:
        pass
    return roots


class PageText:
    """Paths out of the messages of one session (its folder ``folder``)."""

    def __init__(self, folder: Path, roots: Iterable[Path] | None = None) -> None:
        folders = [str(folder), os.path.realpath(folder)]
        own = {f"{f}/{sub}/" for f in folders for sub in SESSION_SUBFOLDERS}
        self._own = sorted(own, key=len, reverse=True)
        """A page's file in the session's folder: named as the page named it."""
        every = [*folders, *(str(r) for r in (roots if roots is not None else server_roots()))]
        self._roots = sorted({r.rstrip("/") for r in every if len(r.rstrip("/")) > 1}, key=len, reverse=True)
        """Folders that may hold spaces: each becomes one word, that the last step then drops."""

    def text(self, text: str) -> str:
        """``text`` with the page's files named as it named them and no other path of the server."""
        if "/" not in text:
            return text
        for own in self._own:
            text = text.replace(own, "")
        for root in self._roots:
            text = text.replace(root + "/", "/_/").replace(root, "/_/_")
        return _PATH.sub(r"\1", text)

    def value(self, value: object) -> object:
        """Every string inside a message's value, as :meth:`text` gives it."""
        if isinstance(value, str):
            return self.text(value)
        if isinstance(value, list):
            return [self.value(v) for v in value]
        if isinstance(value, dict):
            return {k: self.value(v) for k, v in value.items()}
        return value

    def message(self, data: bytes) -> bytes:
        """A message for the page (JSON bytes) without a server path; a chunk as it is."""
        if data.startswith(CHUNK):
            return data
        return json.dumps(self.value(json.loads(data))).encode()
