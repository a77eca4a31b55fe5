"""One seam to C: crslab/_bindings.py is the one module of crslab (and of its tools) that imports the
compiled core, ``crslab._core``; every other module calls the bindings' functions, as PyNaCl's and
argon2-cffi's packages call theirs (docs/architecture.md). Tests of the C core itself may reach it
directly."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SEAM = "crslab/_bindings.py"
CORE = "crslab._core"


def imports_of_the_core(text: str) -> list[int]:
    """The lines of ``text`` (Python) that import the compiled core, in any spelling.

    >>> imports_of_the_core("import crslab._core\\nfrom crslab import _core as c\\n"
    ...                     "from crslab._core import ffi\\nfrom crslab import crs\\n"
    ...                     "importlib.import_module('crslab._core')\\nfrom . import _core\\n")
    [1, 2, 3, 5, 6]
    """
    found = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Import) and any(a.name == CORE or a.name.startswith(CORE + ".")
                                                for a in node.names):
            found.append(node.lineno)
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if module == CORE or (module in ("crslab", "") and any(a.name == "_core" for a in node.names)):
                found.append(node.lineno)
        elif isinstance(node, ast.Constant) and node.value == CORE:  # importlib.import_module("crslab._core")
            found.append(node.lineno)
    return sorted(set(found))


def importers(root: Path) -> dict[str, list[int]]:
    """Every module under ``root``'s crslab/ and tools/ that imports the core, with its lines."""
    found = {}
    for path in sorted([*(root / "crslab").rglob("*.py"), *(root / "tools").rglob("*.py")]):
        lines = imports_of_the_core(path.read_text())
        if lines:
            found[path.relative_to(root).as_posix()] = lines
    return found


def test_the_bindings_are_the_one_module_that_imports_the_c_core():
    assert list(importers(ROOT)) == [SEAM], "call crslab._bindings instead of importing crslab._core"


def test_a_second_module_that_imports_the_core_is_found(tmp_path):
    (tmp_path / "crslab" / "worker").mkdir(parents=True)
    (tmp_path / "tools").mkdir()
    (tmp_path / "crslab" / "_bindings.py").write_text("from crslab._core import ffi, lib\n")
    (tmp_path / "crslab" / "worker" / "board.py").write_text('"""A board."""\n\nfrom crslab import crs\n'
                                                             "from crslab._core import lib\n")
    (tmp_path / "tools" / "bench.py").write_text("def f():\n    import crslab._core\n")
    assert importers(tmp_path) == {"crslab/_bindings.py": [1], "crslab/worker/board.py": [4],
                                   "tools/bench.py": [2]}
