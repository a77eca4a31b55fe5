"""What is wrong with a path given as a lab file, in one line, before anything reads it: a path
that does not exist, a folder (``--lab .``), or a header (``--lab lab.h``: the lab is the ``.c``
file that includes it). Every command that takes a lab file asks :func:`lab_file_problem`, or reads it with
:func:`read_lab_file`.

>>> import tempfile
>>> folder = Path(tempfile.mkdtemp())
>>> _ = (folder / "lab1.c").write_text("void lab(void) {}")
>>> _ = (folder / "mine.h").write_text("#define K 1")
>>> lab_file_problem(folder / "lab1.c") is None
True
>>> lab_file_problem(folder / "nope.c").endswith("nope.c: no such lab file")
True
>>> lab_file_problem(folder).endswith("is a folder, not a lab file: give the lab file in it (lab1.c)")
True
>>> lab_file_problem(folder / "mine.h").endswith("mine.h: is a header, not a lab file: give the .c file "
...                                              "that defines lab()")
True
>>> _ = (folder / "lab1_tour.txt").write_text("# crslab transcript\\n")
>>> print(lab_file_problem(folder / "lab1_tour.txt").split(": ", 1)[1])  # doctest: +NORMALIZE_WHITESPACE
is a transcript (crslab record wrote it), not a lab file: a lab is a .c file; a golden transcript
goes to crslab check --golden
"""

from __future__ import annotations

from pathlib import Path

from crslab.lab.compile_process import LabBuildError

LAB_SUFFIXES = (".c", ".cpp")
HEADER_SUFFIXES = (".h", ".hpp", ".hh")
TRANSCRIPT_MAGIC = b"# crslab transcript"
"""How a golden transcript starts (:data:`crslab.regress.transcript.MAGIC`)."""
NOT_C = {".txt": "a text file", ".log": "a log", ".csv": "a CSV table", ".toml": "a TOML file",
         ".json": "a JSON file", ".md": "a Markdown file", ".mat": "a MATLAB file", ".png": "a picture"}
"""Files given as a lab that are surely not C, by suffix: what each is."""


def _what_it_is(path: Path) -> str | None:
    """What a file that is surely not a lab file is (a transcript, a text file, ...), else None."""
    if path.suffix.lower() in LAB_SUFFIXES:
        return None
    try:
        with path.open("rb") as f:
            start = f.read(len(TRANSCRIPT_MAGIC))
    except OSError:
        start = b""
    if start == TRANSCRIPT_MAGIC:
        return "a transcript (crslab record wrote it)"
    return NOT_C.get(path.suffix.lower())


def lab_file_problem(path: Path) -> str | None:
    """Why ``path`` cannot be a lab file (one line naming it), or None when it can be read as one."""
    if path.is_dir():
        labs = sorted(p.name for p in path.iterdir() if p.suffix.lower() in LAB_SUFFIXES and p.is_file())
        hint = f" ({', '.join(labs[:4])}{', ...' if len(labs) > 4 else ''})" if labs else " (it holds none)"
        return f"{path}: is a folder, not a lab file: give the lab file in it{hint}"
    if not path.exists():
        return f"{path}: no such lab file"
    if path.suffix.lower() in HEADER_SUFFIXES:
        return f"{path}: is a header, not a lab file: give the .c file that defines lab()"
    if not path.is_file():
        return f"{path}: is not a regular file, so not a lab file"
    what = _what_it_is(path)
    if what is not None:
        golden = "; a golden transcript goes to crslab check --golden" if "transcript" in what or \
            path.suffix.lower() == ".txt" else ""
        return f"{path}: is {what}, not a lab file: a lab is a .c file{golden}"
    return None


def read_lab_file(path: Path) -> bytes:
    """The bytes of the lab file ``path``; one that cannot be a lab file (:func:`lab_file_problem`)
    or cannot be read is a :class:`LabBuildError` naming it."""
    problem = lab_file_problem(path)
    if problem:
        raise LabBuildError(problem)
    try:
        return path.read_bytes()
    except OSError as exc:
        raise LabBuildError(f"{path}: cannot be read ({exc.strerror})") from None
