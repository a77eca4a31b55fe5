"""The project carries its own facts: no file cites a document that is not in the repository, and
every citation of docs/framework.md names a section the page has.

The framework's facts live in docs/framework.md (each with its public source) and the protocols'
byte layouts in docs/host-tools.md; code, docs, models, tests and tools cite those. The
forbidden names are spelled in pieces below so that this file, which is scanned too, does not
contain them.
"""

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCANNED = ("crslab", "csrc", "docs", "models", "tests", "tools", "README.md")
OUTSIDE = re.compile("|".join(re.escape(s) for s in (
    "crs" + "-facts",            # the notes the project was started from
    "serial" + "-protocols",     # ditto, the host protocols
    "../" + "shared",            # the folder beside the repository that held them
    "/" + "work/",               # any absolute path on the machine the project was written on
)), re.IGNORECASE)
SECTION_CITE = re.compile(
    r"framework\.md,? (?:sections? |§)(\d+(?:(?:, | and | to |-)\d+)*)")
FRAMEWORK = ROOT / "docs" / "framework.md"


def scanned_files() -> list[Path]:
    """Every file of the scanned folders that git tracks or would track (ignored files, such as
    build output, left out); without git, every file under them outside caches."""
    try:
        out = subprocess.run(
            ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard", "--", *SCANNED],
            cwd=ROOT, capture_output=True, check=True).stdout
        names = sorted({n for n in out.decode().split("\0") if n})
        return [ROOT / n for n in names if (ROOT / n).is_file()]
    except (OSError, subprocess.CalledProcessError):
        found: list[Path] = []
        for top in SCANNED:
            path = ROOT / top
            found += [path] if path.is_file() else [
                p for p in path.rglob("*")
                if p.is_file() and "__pycache__" not in p.parts and ".venv" not in p.parts]
        return sorted(found)


def text_lines(path: Path) -> list[str]:
    """The file's lines, or none for a binary file."""
    data = path.read_bytes()
    if b"\0" in data:
        return []
    return data.decode("utf-8", errors="replace").splitlines()


def test_the_scan_sees_the_projects_files():
    files = {p.relative_to(ROOT).as_posix() for p in scanned_files()}
    for expected in ("README.md", "docs/framework.md", "csrc/port/framework_facts.h",
                     "models/crs_arm/params.toml", "tests/test_no_outside_citations.py"):
        assert expected in files


def test_no_file_cites_anything_outside_the_repository():
    found = [f"{path.relative_to(ROOT)}:{number}: {line.strip()}"
             for path in scanned_files()
             for number, line in enumerate(text_lines(path), 1) if OUTSIDE.search(line)]
    assert not found, "cite docs/framework.md or docs/host-tools.md instead:\n" + "\n".join(found)


def cited_sections(text: str) -> set[int]:
    """The section numbers `text` cites as 'framework.md section 4', 'sections 2 and 7',
    'sections 3 to 6' or 'framework.md §11'.

    >>> sorted(cited_sections("see docs/framework.md sections 3 to 5 and framework.md §11"))
    [3, 4, 5, 11]
    """
    sections: set[int] = set()
    for match in SECTION_CITE.finditer(text):
        spec = match.group(1)
        for part in re.split(r", | and ", spec):
            ends = re.split(r" to |-", part)
            sections.update(range(int(ends[0]), int(ends[-1]) + 1))
    return sections


def framework_sections() -> dict[int, str]:
    """docs/framework.md's numbered sections: number to body."""
    parts = re.split(r"^## (\d+)\. .*$", FRAMEWORK.read_text(), flags=re.MULTILINE)
    return {int(parts[i]): parts[i + 1] for i in range(1, len(parts), 2)}


def test_every_citation_of_framework_md_names_one_of_its_sections():
    have = framework_sections()
    assert sorted(have) == list(range(1, len(have) + 1)), "sections numbered 1, 2, 3, ..."
    bad, cites = [], 0
    for path in scanned_files():
        for number, line in enumerate(text_lines(path), 1):
            for section in cited_sections(line):
                cites += 1
                if section not in have:
                    bad.append(f"{path.relative_to(ROOT)}:{number}: section {section}")
    assert cites >= 40, "the code and docs cite the page's sections"
    assert not bad, "docs/framework.md has no such section:\n" + "\n".join(bad)


def test_every_section_of_framework_md_names_its_sources():
    sources = re.compile(r"STARTER|PICCOLO|RSMEI|TF-SRC|\bTF\b|\bPKS\b|\bAMR\b|SPRU514|https://"
                         r"|not public|crslab's|[\w-]+/[\w.-]+`?, `|section \d+")
    for number, body in framework_sections().items():
        assert sources.search(body), f"section {number} names no source"
