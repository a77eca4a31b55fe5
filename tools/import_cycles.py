"""List the import cycles of crslab's code: Python modules and packages, and C files.

A cycle is a group of modules (or files) each of which, through the others, depends on itself:
none of them can be read, tested or changed alone. The script reads the sources as text and
runs nothing:

- **Python** (``crslab/``, from each file's syntax tree): every ``import`` and ``from ... import``
  of a crslab module counts, wherever it stands (inside a function or under ``TYPE_CHECKING``
  too: a deferred import hides a cycle, it does not remove it). A module depends on the module
  it names (``from crslab.run import simulation`` names ``crslab.run.board_run``). The same edges are
  also taken between packages (``crslab.run`` depends on ``crslab.regress`` when one of its
  modules imports one of the other's), and a cycle there is listed too.
- **C** (``csrc/``, but the lab files in ``csrc/labs`` and the test programs in ``csrc/tests``,
  which nothing includes or calls): a file depends on each header it includes (``#include
  "x.h"``) and on each file that defines a function, not ``static``, that it calls or names (a
  function pointer). A header that only declares depends on nothing but its own includes, so
  ``a.c`` calling ``b.c`` while ``b.c`` includes ``a.h`` for a type is no cycle; ``b.c`` calling
  back into ``a.c`` is.

Each cycle is printed with its shortest loop, then every dependency inside it with the file and
line that makes it: the places to cut. Exit status 0 with ``no import cycles``, else 1.

    .venv/bin/python tools/import_cycles.py                # crslab/ and csrc/
    .venv/bin/python tools/import_cycles.py --root DIR     # another checkout (its crslab/, csrc/)

``tests/test_import_cycles.py`` runs it in the suite.
"""

from __future__ import annotations

import argparse
import ast
import re
import sys
from collections import deque
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

PACKAGE = "crslab"
C_ROOT = "csrc"
C_LEAVES = ("labs", "tests")
"""Folders of ``csrc`` left out: lab files and test programs, which nothing includes or calls."""


@dataclass(frozen=True)
class Edge:
    """``source`` depends on ``target`` because of ``why`` at ``where`` (file:line)."""

    source: str
    target: str
    where: str
    why: str


# -- Python -------------------------------------------------------------------------------------

def python_modules(root: Path) -> dict[str, Path]:
    """Every module of the package under ``root`` (``crslab/``), by dotted name."""
    out = {}
    for path in sorted((root / PACKAGE).rglob("*.py")):
        parts = list(path.relative_to(root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def _imported(node: ast.Import | ast.ImportFrom, module: str, is_package: bool) -> list[str]:
    """The dotted names one import statement of ``module`` names (a module, or a module's member)."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    base = node.module or ""
    if node.level:
        here = module.split(".") if is_package else module.split(".")[:-1]
        here = here[: len(here) - (node.level - 1)]
        base = ".".join([*here, base] if base else here)
    return [f"{base}.{alias.name}" for alias in node.names] + [base]


def python_edges(root: Path) -> list[Edge]:
    """Every import of one crslab module by another, with its file and line."""
    modules = python_modules(root)
    edges = []
    for module, path in modules.items():
        tree = ast.parse(path.read_text(), filename=str(path))
        for node in ast.walk(tree):
            if not isinstance(node, (ast.Import, ast.ImportFrom)):
                continue
            names = _imported(node, module, path.name == "__init__.py")
            # `from p import m` names the module p.m when there is one, else p itself
            targets = []
            for name in names:
                while name and name not in modules:
                    name = name.rpartition(".")[0]
                if name:
                    targets.append(name)
            if isinstance(node, ast.ImportFrom) and len(targets) > 1:
                base = targets[-1]
                deeper = [t for t in targets[:-1] if t != base]
                targets = deeper or [base]
            for target in dict.fromkeys(targets):
                if target != module and not module.startswith(target + "."):  # a parent package
                    where = f"{path.relative_to(root)}:{node.lineno}"
                    edges.append(Edge(module, target, where, f"imports {target}"))
    return edges


def package_of(module: str) -> str:
    """The top-level package (or module) of crslab a module belongs to.

    >>> package_of("crslab.run.board_run"), package_of("crslab.cache"), package_of("crslab")
    ('crslab.run', 'crslab.cache', 'crslab')
    """
    return ".".join(module.split(".")[:2])


def package_edges(edges: Iterable[Edge]) -> list[Edge]:
    """The module imports that cross from one of crslab's packages to another, as package edges."""
    out = []
    for e in edges:
        a, b = package_of(e.source), package_of(e.target)
        if a != b and PACKAGE not in (a, b):
            out.append(Edge(a, b, e.where, e.why))
    return out


# -- C ------------------------------------------------------------------------------------------

_COMMENT_OR_LITERAL = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.DOTALL)
_INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*"', re.MULTILINE)
_DIRECTIVE = re.compile(r"^[ \t]*#(?:[^\n]*\\\n)*[^\n]*", re.MULTILINE)
_IDENT = re.compile(r"\b[A-Za-z_]\w*\b")
_DEFINITION = re.compile(r"\b([A-Za-z_]\w*)\s*\(([^()]|\([^()]*\))*\)\s*$")
_NOT_FUNCTIONS = {"if", "for", "while", "switch", "return", "sizeof", "defined"}


def _blank(match: re.Match[str]) -> str:
    """A comment or literal as blanks, its newlines kept (so line numbers stay)."""
    text = match.group(0)
    keep = '""' if text.startswith('"') else ("''" if text.startswith("'") else "")
    return keep + re.sub(r"[^\n]", " ", text[len(keep):])


def c_files(root: Path) -> dict[Path, str]:
    """Every C file under ``csrc/`` (but its leaves), and its name in the report."""
    base = root / C_ROOT
    out = {}
    for path in sorted([*base.rglob("*.c"), *base.rglob("*.h")]):
        rel = path.relative_to(root)
        if rel.parts[1] in C_LEAVES:
            continue
        out[path] = str(rel)
    return out


@dataclass
class _CFile:
    path: Path
    name: str
    includes: list[tuple[str, int]]  # (the included name, line)
    defines: dict[str, bool]  # function name -> static
    uses: list[tuple[str, int]]  # (an identifier inside a function body, line)


def _read_c(path: Path, name: str) -> _CFile:
    raw = path.read_text(errors="replace")
    text = _COMMENT_OR_LITERAL.sub(_blank, raw)  # as long as raw: an offset in one is one in the other
    includes = [(raw[m.end():raw.index('"', m.end())], text.count("\n", 0, m.start()) + 1)
                for m in _INCLUDE.finditer(text)]
    code = _DIRECTIVE.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)
    defines: dict[str, bool] = {}
    uses: list[tuple[str, int]] = []
    depth, start, body_from = 0, 0, -1
    for i, ch in enumerate(code):
        if ch == "{":
            if depth == 0:
                head = code[start:i]
                m = _DEFINITION.search(head)
                if m and m.group(1) not in _NOT_FUNCTIONS and "=" not in head:
                    defines[m.group(1)] = bool(re.search(r"\bstatic\b", head))
                    body_from = i
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0:
                if body_from >= 0:
                    line0 = code.count("\n", 0, body_from) + 1
                    body = code[body_from:i]
                    for m in _IDENT.finditer(body):
                        uses.append((m.group(0), line0 + body.count("\n", 0, m.start())))
                body_from, start = -1, i + 1
        elif ch == ";" and depth == 0:
            start = i + 1
    return _CFile(path, name, includes, defines, uses)


def c_edges(root: Path) -> list[Edge]:
    """Every include of another file and every use of a function another file defines."""
    files = [_read_c(path, name) for path, name in c_files(root).items()]
    by_name: dict[str, list[Path]] = {}
    for f in files:
        by_name.setdefault(f.path.name, []).append(f.path)
    name_of = {f.path: f.name for f in files}
    definers: dict[str, set[str]] = {}
    for f in files:
        for name, static in f.defines.items():
            if not static:
                definers.setdefault(name, set()).add(f.name)
    edges = []
    for f in files:
        for name, line in f.includes:
            near = f.path.parent / name
            target = name_of.get(near.resolve()) or name_of.get(near)
            if target is None and len(by_name.get(Path(name).name, [])) == 1:
                target = name_of[by_name[Path(name).name][0]]
            if target is not None and target != f.name:
                edges.append(Edge(f.name, target, f"{f.path.relative_to(root)}:{line}", f"includes {name}"))
        seen = set()
        for name, line in f.uses:
            if name in f.defines:
                continue  # its own (a static of the same name shadows another file's)
            for target in sorted(definers.get(name, ())):
                if target != f.name and (name, target) not in seen:
                    seen.add((name, target))
                    edges.append(Edge(f.name, target, f"{f.path.relative_to(root)}:{line}",
                                      f"uses {name}() of {target}"))
    return edges


# -- cycles -------------------------------------------------------------------------------------

def cycles(edges: Iterable[Edge]) -> list[list[str]]:
    """The strongly connected groups of more than one node, each sorted, in a stable order
    (Tarjan's algorithm, iterative).

    >>> cycles([Edge("a", "b", "", ""), Edge("b", "a", "", ""), Edge("b", "c", "", "")])
    [['a', 'b']]
    """
    graph: dict[str, list[str]] = {}
    for e in edges:
        graph.setdefault(e.source, []).append(e.target)
        graph.setdefault(e.target, [])
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, 0)]
        while work:
            node, child = work.pop()
            if child == 0:
                index[node] = low[node] = len(index)
                stack.append(node)
                on_stack.add(node)
            targets = graph[node]
            if child < len(targets):
                work.append((node, child + 1))
                nxt = targets[child]
                if nxt not in index:
                    work.append((nxt, 0))
                elif nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
                continue
            if low[node] == index[node]:
                group = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    group.append(member)
                    if member == node:
                        break
                if len(group) > 1:
                    groups.append(sorted(group))
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
    return sorted(groups)


def shortest_loop(group: list[str], edges: Iterable[Edge]) -> list[str]:
    """The shortest path from the group's first node back to itself, inside the group."""
    members = set(group)
    graph: dict[str, list[str]] = {}
    for e in edges:
        if e.source in members and e.target in members:
            graph.setdefault(e.source, []).append(e.target)
    start = group[0]
    came_from: dict[str, str] = {}
    queue = deque([start])
    while queue:
        node = queue.popleft()
        for nxt in sorted(set(graph.get(node, ()))):
            if nxt == start:
                path = [node]
                while path[-1] != start:
                    path.append(came_from[path[-1]])
                return [*reversed(path), start]
            if nxt not in came_from:
                came_from[nxt] = node
                queue.append(nxt)
    return [start]  # pragma: no cover - a group always loops


def report(title: str, edges: list[Edge]) -> list[str]:
    """The lines that describe each cycle of ``edges``."""
    lines = []
    for group in cycles(edges):
        members = set(group)
        lines.append(f"{title} cycle: {' -> '.join(shortest_loop(group, edges))}")
        inside = sorted({(e.source, e.target, e.where, e.why) for e in edges
                         if e.source in members and e.target in members})
        lines.extend(f"    {where}: {why}" for _source, _target, where, why in inside)
    return lines


def find_all(root: Path) -> list[str]:
    """Every cycle of the checkout at ``root``, as report lines (none: no cycles)."""
    lines = []
    if (root / PACKAGE).is_dir():
        modules = python_edges(root)
        lines += report("python module", modules)
        lines += report("python package", package_edges(modules))
    if (root / C_ROOT).is_dir():
        lines += report("C", c_edges(root))
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="tools/import_cycles.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", type=Path, default=Path(__file__).resolve().parents[1],
                        help="the checkout whose crslab/ and csrc/ to read (default: this one)")
    args = parser.parse_args(argv)
    if not (args.root / PACKAGE).is_dir() and not (args.root / C_ROOT).is_dir():
        print(f"tools/import_cycles.py: {args.root} has neither {PACKAGE}/ nor {C_ROOT}/", file=sys.stderr)
        return 2
    lines = find_all(args.root)
    print("\n".join(lines) if lines else "no import cycles")
    return 1 if lines else 0


if __name__ == "__main__":
    sys.exit(main())
