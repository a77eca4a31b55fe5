"""Compile a lab file (unmodified) with host gcc into a shared object with the emulated board.

The lab is compiled as C11 (never a GNU dialect, so globals named ``gamma``, ``y0`` or ``j1``
do not clash with glibc's math declarations), a ``.cpp`` file holding C is compiled as C, and
the object is linked with ``-Wl,-Bsymbolic`` so lab globals named like libc functions
(``time``, ``index``, ``step``) bind to the lab's own definitions. Builds are cached by the
content of the lab, of every board source and of the flags, so a second run starts at once.
"""

from __future__ import annotations

import hashlib
import os
import re
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from crslab.lab.watched import WatchedVar, find_watched

ROOT = Path(__file__).resolve().parents[2]
CSRC = ROOT / "csrc"
SHIM_INCLUDE = CSRC / "board" / "include"
KIN = CSRC / "kin"
SIM = CSRC / "sim"
DEFAULT_LAB = CSRC / "labs" / "lab1_kinematics.c"
BOARD_SOURCES = sorted(SIM.glob("*.c")) + sorted(KIN.glob("*.c"))
BOARD_HEADERS = sorted(SIM.glob("*.h")) + sorted(KIN.glob("*.h")) + sorted(SHIM_INCLUDE.glob("*.h"))

COMPILE_TIMEOUT_S = 60.0
INCLUDES = ["-I", str(SHIM_INCLUDE), "-I", str(KIN), "-I", str(SIM)]
LAB_FLAGS = ["-std=c11", "-O2", "-fPIC", "-w", "-fno-common"]
BOARD_FLAGS = ["-std=c11", "-O2", "-fPIC", "-Wall", "-Wextra", "-Werror", "-fno-math-errno"]
# ASan finds out-of-bounds reads and writes (and says which); UBSan the rest (overflow,
# misalignment, bad shifts), so UBSan's own array-bounds and object-size checks are left to ASan.
SANITIZE_FLAGS = ["-fsanitize=address,undefined", "-fno-sanitize=bounds,object-size",
                  "-fno-omit-frame-pointer", "-g", "-O1"]
LINK_LIBS = ["-lm", "-lmvec"] if os.uname().machine == "x86_64" else ["-lm"]

GEN_A, GEN_B = 1, 2
SERIAL_LIMIT = {GEN_A: 2048, GEN_B: 136}  # bytes in the real serial_printf buffer
_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.MULTILINE)


class LabBuildError(Exception):
    """The lab could not be built; ``diagnostics`` holds gcc's own messages."""

    def __init__(self, message: str, diagnostics: str = "") -> None:
        super().__init__(message)
        self.diagnostics = diagnostics


@dataclass(frozen=True)
class LabBuild:
    """A compiled lab: the shared object and what was learned from the source."""

    source: Path
    shared_object: Path
    generation: int
    sanitized: bool
    digest: str
    watched: tuple[WatchedVar, ...] = field(default=())

    @property
    def serial_line_limit(self) -> int:
        """Bytes the real board's serial buffer holds for this framework generation."""
        return SERIAL_LIMIT[self.generation]


def detect_generation(source_text: str) -> int:
    """Which framework the file was written for, from its includes.

    >>> detect_generation('#include "F28335Serial.h"')
    2
    >>> detect_generation('#include <coecsl.h>')
    1
    """
    includes = set(_INCLUDE.findall(source_text))
    return GEN_B if "F28335Serial.h" in includes and "coecsl.h" not in includes else GEN_A


def cache_dir() -> Path:
    """Where builds are kept: ``$CRSLAB_CACHE_DIR``, else ``~/.cache/crslab``, else (a read-only
    home) a folder in the system's temporary directory."""
    env = os.environ.get("CRSLAB_CACHE_DIR")
    base = Path(env) if env else Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "crslab"
    try:
        base.mkdir(parents=True, exist_ok=True)
        if os.access(base, os.W_OK):
            return base
    except OSError:
        if env:
            raise LabBuildError(f"CRSLAB_CACHE_DIR={env} cannot be created") from None
    fallback = Path(tempfile.gettempdir()) / f"crslab-cache-{os.getuid()}"
    fallback.mkdir(parents=True, exist_ok=True)
    return fallback


def _digest(parts: list[bytes]) -> str:
    h = hashlib.sha256()
    for p in parts:
        h.update(len(p).to_bytes(8, "little"))
        h.update(p)
    return h.hexdigest()[:20]


def _gcc(args: list[str], what: str) -> None:
    try:
        r = subprocess.run(["gcc", *args], capture_output=True, text=True, timeout=COMPILE_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        raise LabBuildError(f"{what}: gcc took longer than {COMPILE_TIMEOUT_S:.0f} s") from None
    except FileNotFoundError:
        raise LabBuildError("gcc was not found on PATH; crslab needs a C compiler") from None
    if r.returncode != 0:
        raise LabBuildError(f"{what} does not compile", r.stderr)


def _board_objects(sanitize: bool) -> list[Path]:
    """The board, framework and kinematics objects, built once per content and flags."""
    flags = BOARD_FLAGS + (SANITIZE_FLAGS if sanitize else [])
    digest = _digest([" ".join(flags).encode()] + [p.read_bytes() for p in BOARD_SOURCES + BOARD_HEADERS])
    out_dir = cache_dir() / f"board-{digest}"
    objects = [out_dir / f"{p.parent.name}_{p.stem}.o" for p in BOARD_SOURCES]
    if all(o.exists() for o in objects):
        return objects
    out_dir.mkdir(parents=True, exist_ok=True)
    for src, obj in zip(BOARD_SOURCES, objects):
        tmp = obj.with_suffix(f".{os.getpid()}.tmp")
        _gcc([*flags, *INCLUDES, "-c", str(src), "-o", str(tmp)], f"crslab's board source {src.name}")
        tmp.replace(obj)
    return objects


def build_lab(source: Path | None = None, *, sanitize: bool = False) -> LabBuild:
    """Compile ``source`` (default: crslab's Lab 1) and link it with the board; cached.

    Raises :class:`LabBuildError` for a missing file or a file that does not compile.
    """
    src = Path(source) if source is not None else DEFAULT_LAB
    if not src.is_file():
        raise LabBuildError(f"{src}: no such lab file")
    try:
        text_bytes = src.read_bytes()
    except OSError as exc:
        raise LabBuildError(f"{src}: cannot be read ({exc.strerror})") from None
    text = text_bytes.decode("utf-8", "replace")
    generation = detect_generation(text)
    flags = LAB_FLAGS + (SANITIZE_FLAGS if sanitize else [])
    objects = _board_objects(sanitize)
    digest = _digest([text_bytes, " ".join(flags).encode(), src.suffix.encode()]
                     + [o.parent.name.encode() for o in objects[:1]])
    out_dir = cache_dir() / f"lab-{digest}"
    so = out_dir / "lab.so"
    if not so.exists():
        out_dir.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=out_dir) as tmp:
            obj = Path(tmp) / "lab.o"
            # compile the user's own path so gcc's messages name the user's file and line
            _gcc([*flags, *INCLUDES, "-x", "c", "-c", str(src), "-o", str(obj)], src.name)
            tmp_so = Path(tmp) / "lab.so"
            _gcc(["-shared", "-Wl,-Bsymbolic", *(["-fsanitize=address,undefined"] if sanitize else []),
                  "-o", str(tmp_so), str(obj), *map(str, objects), *LINK_LIBS], f"{src.name} (link)")
            tmp_so.replace(so)
    return LabBuild(source=src, shared_object=so, generation=generation, sanitized=sanitize, digest=digest,
                    watched=tuple(find_watched(text)))
