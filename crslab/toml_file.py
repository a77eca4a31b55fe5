"""Reading a user's TOML file (a plant file, a friction table, a robot): anything wrong with the
file itself is one error naming it, never a traceback."""

from __future__ import annotations

import tomllib
from collections.abc import Callable
from pathlib import Path


def read_toml(path: Path, what: str, error: Callable[[str], Exception]) -> dict:
    """The tables of the TOML file ``path``. A missing file, one that cannot be read and one that
    is not TOML raise ``error(message)``, the message naming the file (``what`` says what kind).

    >>> read_toml(Path("/nonexistent/arm.toml"), "plant file", ValueError)
    Traceback (most recent call last):
    ...
    ValueError: /nonexistent/arm.toml: no such plant file
    """
    try:
        with path.open("rb") as f:
            return tomllib.load(f)
    except FileNotFoundError:
        raise error(f"{path}: no such {what}") from None
    except OSError as exc:
        raise error(f"{path}: cannot be read ({exc.strerror})") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise error(f"{path}: not valid TOML: {exc}") from None
