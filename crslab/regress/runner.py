"""What a golden file's header says produced its transcript (crslab's version, the lab, the
scenario, the plant, the world), for the regression commands (record, check, grade) and the pytest
plugin; they run the lab with :func:`crslab.run.assemble.run_kept`."""

from __future__ import annotations

from pathlib import Path

from crslab import __version__
from crslab.framework_facts import TICKS_PER_S
from crslab.regress.transcript import DEFAULT_PLANT, DEFAULT_WORLD, sha256_of
from crslab.worker.config import RunConfig
from crslab.world import WORLD_NAMES


def run_header(config: RunConfig, end_tick: int, scenario_arg: str | None,
               plant_arg: str | Path | None = None, world_arg: str | Path | None = None) -> dict[str, str]:
    """The golden-file header fields that say what produced a transcript: crslab's version, the
    lab and scenario (names and content hashes) and the options that change what is printed,
    the plant file (``plant_arg``, as given; None: crslab's own arm) and the world (``world_arg``, as
    given: a built-in's name or a file; None: free air) among them."""
    source = Path(config.scenario.source)
    try:
        scenario_hash = sha256_of(source.read_bytes())
    except OSError:
        scenario_hash = "unknown"
    return {
        "crslab": __version__,
        "lab": config.build.source.name,
        "lab_sha256": sha256_of(config.build.source.read_bytes()),
        "scenario": scenario_arg or config.scenario.name,
        "scenario_sha256": scenario_hash,
        "end_s": f"{end_tick / TICKS_PER_S:.3f}",
        "rest_motor_rad": " ".join(repr(float(v)) for v in config.rest_motor_rad),
        "startup_delay": "yes" if config.startup_ticks else "no",
        "motor_board": config.motor_board_model,
        **plant_fields(plant_arg),
        **world_fields(world_arg),
    }


def world_fields(world_arg: str | Path | None) -> dict[str, str]:
    """The header's ``world`` (and, for a world file, its ``world_sha256``).

    >>> world_fields(None), world_fields("contest")
    ({'world': 'none'}, {'world': 'contest'})
    """
    if world_arg is None or str(world_arg) in WORLD_NAMES:
        return {"world": str(world_arg or DEFAULT_WORLD)}
    try:
        digest = sha256_of(Path(world_arg).read_bytes())
    except OSError:
        digest = "unknown"
    return {"world": str(world_arg), "world_sha256": digest}


def plant_fields(plant_arg: str | Path | None) -> dict[str, str]:
    """The header's ``plant`` (and, for a file, its ``plant_sha256``)."""
    if plant_arg is None:
        return {"plant": DEFAULT_PLANT}
    try:
        digest = sha256_of(Path(plant_arg).read_bytes())
    except OSError:
        digest = "unknown"
    return {"plant": str(plant_arg), "plant_sha256": digest}
