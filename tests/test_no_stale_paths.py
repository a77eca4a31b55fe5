"""Comments name files that exist: every path of the project (``crslab/...``, ``csrc/...``,
``docs/...``) and every dotted name of crslab (``crslab.worker.board.Board``) that a comment, a
docstring or a page of the docs names is a file, a folder, a module or a name defined in its
module, so a file that moves takes its mentions along. A sibling of
tests/test_no_outside_citations.py (which keeps citations inside the repository)."""

from __future__ import annotations

import ast
import io
import re
import tokenize
from functools import cache
from pathlib import Path

from test_no_outside_citations import ROOT, scanned_files, text_lines

TOPS = ("crslab", "csrc", "docs", "models", "tests", "tools")
BUILT = ("crslab/_core", "crslab/_data")
"""What a build makes (the compiled C core, the wheel's data folder): named, never tracked."""
PATH = re.compile(r"(?<![\w./-])((?:" + "|".join(TOPS) + r")/[\w./*{}<>-]*[\w*}>])")
RELATIVE = re.compile(r"(?<![\w./-])([a-z_]\w*/(?:\w+/)*\w+\.(?:py|c|h|md|toml|xml|js))\b")
DOTTED = re.compile(r"(?<![\w./-])(crslab(?:\.\w+)+)")
PLACEHOLDER = re.compile(r"(?:^|[/.])[A-Z]+(?:[/.]|$)|[*{<]|_$")
"""A path written as a pattern (``crslab/worlds/NAME.toml``, ``tools/benchmarks/bench_*.py``, a
prefix such as ``csrc/tests/test_``)."""
EXAMPLES = {
    "tests/test_x.py": "README.md: how to run any one test file",
    "tests/run.sh": "docs/autograder.md: a file of a PrairieLearn question's folder",
    "tests/test_lab1.py": "docs/first-lab.md: a file of a student's own repository",
}
"""Paths the docs name in someone else's tree, which are not this project's files."""


@cache
def tracked() -> tuple[frozenset[str], frozenset[str]]:
    """The project's files and folders, as paths from its root."""
    files = frozenset(p.relative_to(ROOT).as_posix() for p in scanned_files())
    folders = frozenset(q.as_posix() for f in files for q in Path(f).parents if q.as_posix() != ".")
    return files, folders


def comments(path: Path) -> list[tuple[int, str]]:
    """The comments and docstrings of a Python or C file, the whole text of a page, as (line, text)."""
    if path.suffix == ".py":
        return python_comments(path.read_text())
    if path.suffix in (".c", ".h", ".js"):
        return c_comments(path.read_text())
    return list(enumerate(text_lines(path), 1))


def python_comments(text: str) -> list[tuple[int, str]]:
    """``#`` comments and docstrings, line by line.

    >>> python_comments("'''Doc: a/b.py.'''\\nx = 'not/this.py'  # but this/one.py\\n")
    [(1, 'Doc: a/b.py.'), (2, '# but this/one.py')]
    """
    found = [(tok.start[0], tok.string) for tok in tokenize.generate_tokens(io.StringIO(text).readline)
             if tok.type == tokenize.COMMENT]
    for node in ast.walk(ast.parse(text)):
        text_node = node.value if isinstance(node, ast.Expr) else None
        if isinstance(text_node, ast.Constant) and isinstance(text_node.value, str):
            found += prose(node.lineno, text_node.value)
    return sorted(found)


def prose(first: int, doc: str) -> list[tuple[int, str]]:
    """A docstring's lines but its examples (a ``>>>`` line and what follows it up to a blank line:
    data, not names of the project's files).

    >>> prose(1, "See a/b.py.\\n>>> f('x/y.py')\\n'x/y.py'\\n\\nAnd c/d.py.")
    [(1, 'See a/b.py.'), (4, ''), (5, 'And c/d.py.')]
    """
    lines, example = [], False
    for i, line in enumerate(doc.splitlines()):
        example = line.lstrip().startswith(">>>") or (example and line.strip() != "")
        if not example:
            lines.append((first + i, line))
    return lines


def c_comments(text: str) -> list[tuple[int, str]]:
    """``/* */`` and ``//`` comments, line by line (a string's ``/*`` is not one).

    >>> c_comments('int a; /* one/a.c\\n two/b.h */ char *s = "/* no */"; // three/c.c\\n')
    [(1, ' one/a.c'), (2, ' two/b.h '), (2, ' three/c.c')]
    """
    found = []
    for m in re.finditer(r'"(?:\\.|[^"\\\n])*"|/\*(.*?)\*/|//([^\n]*)', text, re.S):
        body = m.group(1) if m.group(1) is not None else m.group(2)
        if body is None:
            continue
        first = text.count("\n", 0, m.start()) + 1
        found += [(first + i, line) for i, line in enumerate(body.split("\n"))]
    return found


def path_exists(name: str) -> bool:
    """A file or folder of the project, or a name in one of its modules (``tests/waiting.py``'s
    ``tests/waiting.LineWatcher``)."""
    files, folders = tracked()
    module, _, _ = name.rpartition(".")
    return name in files or name in folders or name.startswith(BUILT) or module + ".py" in files


@cache
def tails() -> frozenset[str]:
    """Every path of a file from inside one of its folders (``crslab/worker/board.py``: also
    ``worker/board.py``)."""
    files, _ = tracked()
    return frozenset(f.split("/", i)[-1] for f in files for i in range(1, f.count("/") + 1))


def relative_exists(name: str) -> bool:
    """A path from inside a folder (``worker/board.py``, ``plant/push.h``): some file ends with it."""
    return name in tails()


def dotted_exists(name: str) -> bool:
    """``crslab.a.b.C``: a module, or a name the longest module among its prefixes defines (or a
    module or folder beside it)."""
    files, folders = tracked()
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        base = "/".join(parts[:k])
        module = next((m for m in (base + ".py", base + "/__init__.py") if m in files), None)
        if module is None:
            if k == len(parts) and (base in folders or base.startswith(BUILT)):
                return True
            continue
        if k == len(parts):
            return True
        first = parts[k]
        if first.startswith("__") or f"{base}/{first}.py" in files or f"{base}/{first}" in folders:
            return True
        defined = (rf"^\s*(?:async\s+def|def|class)\s+{first}\b|^\s*{first}\s*[:=]"
                   rf"|^\s*(?:from|import)\b.*\b{first}\b")
        return re.search(defined, (ROOT / module).read_text(), re.M) is not None
    return name.startswith("crslab._core")


def stale(where: str, lines: list[tuple[int, str]]) -> list[str]:
    """Each name of a missing file or module in ``lines`` (comments of the file ``where``):
    ``FILE:LINE: NAME``."""
    _, folders = tracked()
    roots = {Path(f).name for f in folders if Path(f).parent.as_posix() in ("crslab", "csrc")}
    found = []
    for number, line in lines:
        for m in PATH.finditer(line):
            name = m.group(1).rstrip(".")
            if not PLACEHOLDER.search(name) and name not in EXAMPLES and not path_exists(name):
                found.append(f"{where}:{number}: {name}")
        for m in RELATIVE.finditer(line):
            name = m.group(1)
            if name.split("/")[0] in roots and not name.startswith(TOPS) and not relative_exists(name):
                found.append(f"{where}:{number}: {name}")
        for m in DOTTED.finditer(line):
            if not PLACEHOLDER.search(m.group(1)) and not dotted_exists(m.group(1)):
                found.append(f"{where}:{number}: {m.group(1)}")
    return found


def scanned() -> list[Path]:
    return [p for p in scanned_files() if p.suffix in (".py", ".c", ".h", ".md", ".js", ".toml")
            ]


def test_every_file_a_comment_names_exists():
    found = [problem for path in scanned()
             for problem in stale(path.relative_to(ROOT).as_posix(), comments(path))]
    assert not found, "a comment names a file or module that does not exist:\n" + "\n".join(found)


def test_a_moved_file_or_name_is_found_and_a_present_one_is_not():
    lines = [(1, "laid out by crslab/host_tools/c28x_memory.py (now crslab/lab/c28x_memory.py)"),
             (2, "see worker/nothing.py and worker/board.py, plant/push.h"),
             (3, "crslab.worker.main.WORLD_COLUMNS, crslab.world.world_facts.WORLD_COLUMNS, crslab.run"),
             (4, "crslab/worlds/NAME.toml, tools/benchmarks/bench_*.py, csrc/tests/test_, docs/worlds.md")]
    assert stale("x.c", lines) == ["x.c:1: crslab/host_tools/c28x_memory.py", "x.c:2: worker/nothing.py",
                                   "x.c:3: crslab.worker.main.WORLD_COLUMNS"]
