"""A rerun recording sent to a viewer crslab starts, to an ``.rrd`` file, or both: how ``crslab
sim --rerun/--rrd`` (:mod:`crslab.sinks.rerun_scopes`) and ``crslab serial scope``
(:mod:`crslab.host_tools.scope`) each open theirs, and the Simulink scope they share.

Rerun (whose import starts threads) is imported by the caller and passed in as ``rr``.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

from crslab.scopes.display import missing_display

SIMULINK_ENTITY = "/scopes/simulink"
"""Where Simulink_PlotVar1..4 are logged, in both recordings."""
SIMULINK_NAMES = [f"Simulink_PlotVar{k}" for k in range(1, 5)]


def viewer_executable() -> str | None:
    """The rerun viewer installed with rerun-sdk beside this Python (a venv's bin/), if there is one;
    None lets rerun search the PATH."""
    here = Path(sys.executable).parent / "rerun"
    return str(here) if here.is_file() else None


def open_recording(rr: object, name: str, *, spawn: bool, rrd_path: Path | str | None,
                   on_status: Callable[[str], None], prefix: str = "",
                   blueprint: object | None = None) -> tuple[object, bool]:
    """A new recording named ``name``, sent to a viewer started now (``spawn``) and/or written to
    ``rrd_path``; returns it and whether it goes anywhere. A viewer that cannot start (no display,
    or it fails) is one line to ``on_status`` (after ``prefix``), and the run goes on without it."""
    rec = rr.RecordingStream("crslab", send_properties=False)  # type: ignore[attr-defined]
    sinks: list[object] = []
    if spawn:
        why = missing_display()
        if why:
            on_status(f"{prefix}{why}; running without the rerun viewer"
                      + ("" if rrd_path else " (--rrd FILE saves a recording to open later)"))
        else:
            try:
                rr.spawn(connect=False, executable_path=viewer_executable(), recording=rec)  # type: ignore[attr-defined]
                sinks.append(rr.GrpcSink())  # type: ignore[attr-defined]
            except Exception as exc:  # noqa: BLE001 - any failure to start it is one line
                why = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
                on_status(f"{prefix}the rerun viewer did not start ({why}); running without it")
    if rrd_path is not None:
        sinks.append(rr.FileSink(str(rrd_path)))  # type: ignore[attr-defined]
    if sinks:
        if blueprint is not None:
            rec.set_sinks(*sinks, default_blueprint=blueprint)
        else:
            rec.set_sinks(*sinks)
        rec.send_recording_name(name)
    return rec, bool(sinks)
