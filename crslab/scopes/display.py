"""Whether a window can be opened (the rerun viewer, MuJoCo's viewer)."""

from __future__ import annotations

import os
import sys


def missing_display(environ: dict[str, str] | None = None, platform: str | None = None) -> str | None:
    """Why no window can open here, or None when a display looks available.

    >>> missing_display({}, "linux")
    'no display (neither DISPLAY nor WAYLAND_DISPLAY is set)'
    >>> missing_display({"DISPLAY": ":0"}, "linux") is None
    True
    """
    env = os.environ if environ is None else environ
    platform = sys.platform if platform is None else platform
    if platform.startswith("linux") or "bsd" in platform:
        if not (env.get("DISPLAY") or env.get("WAYLAND_DISPLAY")):
            return "no display (neither DISPLAY nor WAYLAND_DISPLAY is set)"
    return None
