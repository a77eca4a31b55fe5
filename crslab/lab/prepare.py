"""``python -m crslab.lab.prepare``: build zig's C library for the firmware once for this
installation (``make venv`` runs it; ``crslab doctor`` does the same), with its progress on stderr.
A lab's first build then takes seconds, even on a fresh cache (:mod:`crslab.lab.zig`)."""

from __future__ import annotations

from crslab.lab.firmware import prepare_zig
from crslab.lab.zig import ZigMissing


def main() -> None:
    """Prepare it; a failure is one line and exit status 1."""
    try:
        prepare_zig()
    except (RuntimeError, ZigMissing) as exc:
        raise SystemExit(f"crslab: {exc}") from None


if __name__ == "__main__":
    main()
