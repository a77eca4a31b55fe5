"""The build steps pyproject.toml cannot say; all metadata lives in pyproject.toml.

- cffi builds the C core (``crslab._core``) from ``csrc/cffi_build.py``.
- ``csrc/`` and ``models/`` stay at the top of the repository; the wheel carries them as package
  data in ``crslab/_data/`` (``build_py`` below), where :mod:`crslab.resources` finds them. An
  editable install copies nothing: it uses the checkout's own folders.
- The sdist carries all of ``csrc/`` and ``models/`` (``sdist`` below), so a wheel builds from it.
- The C core uses only CPython's stable ABI (cffi builds it ``py_limited_api``, as
  ``_core.abi3.so``), so the wheel is tagged ``cp311-abi3``: one wheel installs on every CPython
  from 3.11 on (``LIMITED_API`` below).
"""

from __future__ import annotations

from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py as _build_py
from setuptools.command.sdist import sdist as _sdist

ROOT = Path(__file__).resolve().parent
PACKAGED = Path("crslab") / "_data"  # crslab.resources.PACKAGED
SKIP_DIRS = {"__pycache__", "tests"}  # csrc/tests: the C core's own tests, not needed at run time
SKIP_SUFFIXES = {".o", ".so", ".pyc", ".tmp"}
LIMITED_API = "cp311"  # the oldest CPython the wheel installs on: pyproject.toml's requires-python


def runtime_files() -> list[Path]:
    """The files of ``csrc/`` and ``models/`` that labs are built and simulated with, relative to
    the repository (not csrc's tests nor its build script)."""
    out = []
    for top in ("csrc", "models"):
        for path in sorted((ROOT / top).rglob("*")):
            rel = path.relative_to(ROOT)
            if not path.is_file() or SKIP_DIRS & set(rel.parts[1:-1]) or path.suffix in SKIP_SUFFIXES:
                continue
            if rel.parent == Path("csrc") and path.suffix == ".py":
                continue
            out.append(rel)
    return out


class build_py(_build_py):  # noqa: N801 - setuptools' command name
    """setuptools' build_py, then csrc/ and models/ copied into crslab/_data/."""

    def run(self) -> None:
        super().run()
        if self.editable_mode:
            return  # the checkout's own csrc/ and models/ are used in place
        for rel in runtime_files():
            target = Path(self.build_lib) / PACKAGED / rel
            self.mkpath(str(target.parent))
            self.copy_file(str(ROOT / rel), str(target), preserve_mode=False)

    def get_outputs(self, include_bytecode: bool = True) -> list[str]:
        outputs = super().get_outputs(include_bytecode)
        if self.editable_mode:
            return outputs
        return outputs + [str(Path(self.build_lib) / PACKAGED / rel) for rel in runtime_files()]


class sdist(_sdist):  # noqa: N801 - setuptools' command name
    """setuptools' sdist plus every file of csrc/ (its tests and build script included) and models/."""

    def make_release_tree(self, base_dir: str, files: list[str]) -> None:
        extra = [str(path.relative_to(ROOT)) for top in ("csrc", "models")
                 for path in sorted((ROOT / top).rglob("*"))
                 if path.is_file() and "__pycache__" not in path.parts and path.suffix not in SKIP_SUFFIXES]
        super().make_release_tree(base_dir, sorted(set(files) | set(extra)))


setup(
    cffi_modules=["csrc/cffi_build.py:ffibuilder"],
    cmdclass={"build_py": build_py, "sdist": sdist},
    options={"bdist_wheel": {"py_limited_api": LIMITED_API}},
)
