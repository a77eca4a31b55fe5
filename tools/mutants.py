"""``make mutants``: does the suite notice a deliberate one-line bug?

Each mutation in ``tools/mutations/*.toml`` names a file, an exact piece of one line of it (it
must occur exactly once in that file) and what to put instead, and the tests that must notice.
The script copies the checkout (every tracked or new, not ignored, file) into a temporary
folder once, checks that the named tests pass on the unmutated copy, then for each mutation:
applies it, runs its tests there (``pytest -x``, crslab imported from the copy; the C core is
rebuilt when the mutation touches it), and puts the line back. A mutation is **killed** when a
test fails (its assertion, or an exception in the test's own body); one whose tests still pass
**survived**: a rule no test pins down. One whose tests were stopped only by an **error** (a
fixture's set-up or tear-down, pytest's own ``E`` in its summary, not a failed test: perhaps
the mutation, perhaps something unrelated such as a fixture's time limit) is said apart, with
the error, and not counted as killed: nothing shows a test noticed the bug. One that breaks the
build or the test collection is **broken** (a mutation should be a plausible bug, not a syntax
error). pytest's outcome is read from its JUnit XML report. Exit 0 only when every mutation was
killed.

Too slow for CI (minutes); run it before resolving an issue that touches ``csrc/board``,
``csrc/board`` or ``crslab/regress``:

    make mutants                               # all of them
    .venv/bin/python tools/mutants.py --list   # what they are
    .venv/bin/python tools/mutants.py -k clamp # those whose name or file contains "clamp"

A mutation entry::

    [[mutation]]
    name = "envelope: th2's upper bound 0.15 rad becomes 0.45"
    file = "csrc/port/framework_facts.h"
    find = "0.15f"
    replace = "0.45f"
    tests = ["tests/test_sim_framework.py"]
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MUTATIONS = ROOT / "tools" / "mutations"
CORE_INPUTS = ("csrc/kin/", "csrc/board/", "csrc/plant/", "csrc/port/", "csrc/cffi_build.py",
               "crslab/cheaders.py")
"""A mutation of one of these changes the compiled C core (``crslab._core``): it is rebuilt."""
TEST_TIMEOUT_S = 900.0
"""A mutant's tests that run longer than this count as killed (a mutant that hangs the suite
is noticed), but the guard is there so that a run always ends."""


@dataclass(frozen=True)
class Mutation:
    """One deliberate bug: in ``file``, the one occurrence of ``find`` becomes ``replace``."""

    name: str
    file: str
    find: str
    replace: str
    tests: tuple[str, ...]
    source: str
    """The mutations file it comes from."""

    def problem(self, root: Path) -> str | None:
        """Why this mutation cannot be applied to the checkout at ``root`` (None if it can)."""
        where = f"{self.source}: {self.name!r}"
        if "\n" in self.find or "\n" in self.replace:
            return f"{where}: find and replace must each lie within one line"
        if self.find == self.replace:
            return f"{where}: replace is the same as find"
        path = root / self.file
        if not path.is_file():
            return f"{where}: no file {self.file}"
        count = path.read_text().count(self.find)
        if count != 1:
            return f"{where}: {self.find!r} occurs {count} times in {self.file} (must be once)"
        if not self.tests:
            return f"{where}: no tests named"
        for test in self.tests:
            file, _, name = test.partition("::")
            if not (root / file).exists():
                return f"{where}: no test file {file}"
            # a test function (its name, a parameter in brackets after it) or a doctest (the dotted
            # name of the function it documents): either is a def in the file
            defined = name.split("[")[0].rsplit(".", 1)[-1]
            if name and not re.search(rf"^\s*(async\s+)?def {re.escape(defined)}\b",
                                      (root / file).read_text(), re.M):
                return f"{where}: no {defined} in {file}"
        return None


def load(folder: Path = MUTATIONS) -> list[Mutation]:
    """Every mutation of every ``*.toml`` file in ``folder``, in file then listed order."""
    out = []
    for path in sorted(folder.glob("*.toml")):
        with path.open("rb") as f:
            data = tomllib.load(f)
        for entry in data.get("mutation", []):
            unknown = set(entry) - {"name", "file", "find", "replace", "tests"}
            if unknown:
                raise ValueError(f"{path.name}: unknown keys {sorted(unknown)} in {entry.get('name')!r}")
            out.append(Mutation(name=entry["name"], file=entry["file"], find=entry["find"],
                                replace=entry["replace"], tests=tuple(entry["tests"]), source=path.name))
    return out


def checkout_files(root: Path) -> list[str]:
    """The files of the checkout as git sees them: tracked, plus new ones not ignored."""
    listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                            cwd=root, check=True, capture_output=True).stdout.decode()
    return [f for f in listed.split("\0") if f and (root / f).is_file()]


def make_copy(root: Path, dest: Path) -> None:
    """Copy the checkout and its built C core to ``dest``."""
    for rel in checkout_files(root):
        target = dest / rel
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(root / rel, target)
    for built in (root / "crslab").glob("_core.*"):
        shutil.copy2(built, dest / "crslab" / built.name)


def rebuild_core(copy: Path, env: dict[str, str]) -> bool:
    """Compile the copy's C core in place (the mutated one); False when it does not build."""
    for built in (copy / "crslab").glob("_core.*"):
        built.unlink()
    # cffi compiles through setuptools, which would read (and validate) the project's own
    # pyproject.toml in the working folder: the build script needs none of it.
    project = copy / "pyproject.toml"
    project.rename(copy / "pyproject.toml.aside")
    try:
        done = subprocess.run([sys.executable, "csrc/cffi_build.py"], cwd=copy, env=env,
                              capture_output=True, text=True)
    finally:
        (copy / "pyproject.toml.aside").rename(project)
    return done.returncode == 0


def run_tests(copy: Path, tests: tuple[str, ...], env: dict[str, str]) -> tuple[str, str]:
    """What pytest made of ``tests`` in ``copy`` (:func:`outcome`), and the line that says why."""
    report = copy.parent / "pytest-report.xml"
    report.unlink(missing_ok=True)
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "--no-header",
           f"--junitxml={report}", *tests]
    try:
        done = subprocess.run(cmd, cwd=copy, env=env, capture_output=True, text=True, timeout=TEST_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return "killed", f"timed out after {TEST_TIMEOUT_S:g} s"
    lines = (done.stdout + done.stderr).strip().splitlines()
    xml = report.read_text() if report.is_file() else ""
    return outcome(done.returncode, xml, lines[-1] if lines else "")


def outcome(status: int, junit_xml: str, tail: str) -> tuple[str, str]:
    """How a pytest run with exit ``status`` and JUnit report ``junit_xml`` ended: ``passed``,
    ``killed`` (a test failed: its ``<failure>``), ``error`` (only errors: a fixture's set-up or
    tear-down, ``<error>``), ``broken`` (no test ran: collection or usage); with the line that
    says why (the first failure's or error's message, else pytest's last line ``tail``).

    >>> ok = '<testsuites><testsuite><testcase name="t"/></testsuite></testsuites>'
    >>> outcome(0, ok, "1 passed")
    ('passed', '1 passed')
    >>> failed = ('<testsuites><testsuite><testcase classname="tests.test_a" name="test_x">'
    ...           '<failure message="assert 1 == 2">...</failure></testcase></testsuite></testsuites>')
    >>> outcome(1, failed, "1 failed")
    ('killed', 'tests.test_a::test_x: assert 1 == 2')
    >>> errored = failed.replace("failure", "error").replace("assert 1 == 2", "failed on setup with X")
    >>> outcome(1, errored, "1 error")
    ('error', 'tests.test_a::test_x: failed on setup with X')
    >>> outcome(2, "", "ERROR collecting tests/test_a.py")
    ('broken', 'ERROR collecting tests/test_a.py')
    """
    if status == 0:
        return "passed", tail
    failures: list[str] = []
    errors: list[str] = []
    try:
        root = ET.fromstring(junit_xml) if junit_xml else None
    except ET.ParseError:
        root = None
    cases = list(root.iter("testcase")) if root is not None else []
    for case in cases:
        name = f"{case.get('classname', '')}::{case.get('name', '')}"
        for kind, found in (("failure", failures), ("error", errors)):
            for element in case.findall(kind):
                message = (element.get("message") or "").strip().splitlines()
                found.append(f"{name}: {message[0] if message else kind}")
    if status == 1 and failures:
        return "killed", failures[0]
    if status == 1 and errors:
        return "error", errors[0]
    return "broken", tail


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="tools/mutants.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("--list", action="store_true", help="list the mutations and exit")
    parser.add_argument("-k", dest="keyword", help="only mutations whose name or file contains this")
    parser.add_argument("--keep", action="store_true", help="keep the temporary copy (its path is printed)")
    args = parser.parse_args(argv)

    try:
        mutations = load()
    except (OSError, ValueError, KeyError, tomllib.TOMLDecodeError) as exc:
        print(f"mutants: cannot read the mutations: {exc}", file=sys.stderr)
        return 2
    if args.keyword:
        mutations = [m for m in mutations if args.keyword in m.name or args.keyword in m.file]
    problems = [p for m in mutations if (p := m.problem(ROOT)) is not None]
    if problems:
        for p in problems:
            print(f"mutants: {p}", file=sys.stderr)
        return 2
    if args.list:
        for m in mutations:
            print(f"{m.source:<16} {m.name}  [{m.file}]")
        print(f"{len(mutations)} mutations")
        return 0
    if not mutations:
        print("mutants: no mutation matches", file=sys.stderr)
        return 2

    tmp = Path(tempfile.mkdtemp(prefix="crslab-mutants-"))
    copy = tmp / "crslab"
    env = dict(os.environ, PYTHONPATH=str(copy), CRSLAB_CACHE_DIR=str(tmp / "cache"),
               PYTHONDONTWRITEBYTECODE="1")
    env.pop("CRSLAB_REQUIRE_ALL", None)
    try:
        print(f"mutants: copying the checkout to {copy}", file=sys.stderr)
        make_copy(ROOT, copy)
        core_backup = tmp / "core"
        core_backup.mkdir()
        for built in (copy / "crslab").glob("_core.*"):
            shutil.copy2(built, core_backup / built.name)
        every_test = tuple(dict.fromkeys(t for m in mutations for t in m.tests))
        print(f"mutants: the {len(every_test)} test targets on the unmutated copy ...", file=sys.stderr)
        verdict, tail = run_tests(copy, every_test, env)
        if verdict != "passed":
            print(f"mutants: the unmutated copy fails its tests ({tail}); fix that first", file=sys.stderr)
            return 2

        survived: list[Mutation] = []
        broken: list[tuple[Mutation, str]] = []
        errored: list[tuple[Mutation, str]] = []
        for i, m in enumerate(mutations, 1):
            path = copy / m.file
            original = path.read_text()
            path.write_text(original.replace(m.find, m.replace, 1))
            started = time.monotonic()
            core = any(m.file.startswith(p) for p in CORE_INPUTS)
            try:
                if core and not rebuild_core(copy, env):
                    verdict, tail = "broken", "the C core does not build"
                else:
                    verdict, tail = run_tests(copy, m.tests, env)
                    verdict = "SURVIVED" if verdict == "passed" else verdict
            finally:
                path.write_text(original)
                if core:
                    for built in (copy / "crslab").glob("_core.*"):
                        built.unlink()
                    for built in core_backup.iterdir():
                        shutil.copy2(built, copy / "crslab" / built.name)
            if verdict == "SURVIVED":
                survived.append(m)
            elif verdict == "broken":
                broken.append((m, tail))
            elif verdict == "error":
                errored.append((m, tail))
            seconds = time.monotonic() - started
            print(f"[{i}/{len(mutations)}] {verdict:<8} {m.name} ({seconds:.0f} s)"
                  + (f": {tail}" if verdict in ("broken", "error") else ""), flush=True)
    finally:
        if args.keep:
            print(f"mutants: the copy is kept in {copy}", file=sys.stderr)
        else:
            shutil.rmtree(tmp, ignore_errors=True)

    killed = len(mutations) - len(survived) - len(broken) - len(errored)
    print(f"mutants: {killed} of {len(mutations)} killed by a failing test, {len(errored)} stopped by an "
          f"error (not a failed test), {len(survived)} survived, {len(broken)} broken")
    for m in survived:
        print(f"  survived: {m.name} [{m.file}: {m.find!r} -> {m.replace!r}]")
    for m, tail in errored:
        print(f"  stopped by an error: {m.name} [{m.file}]: {tail}")
    for m, tail in broken:
        print(f"  broken: {m.name} [{m.file}]: {tail}")
    return 0 if not survived and not broken and not errored else 1


if __name__ == "__main__":
    sys.exit(main())
