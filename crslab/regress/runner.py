"""Run one prepared lab configuration as fast as possible and keep what it printed, for the
regression commands (record, check, grade) and the pytest plugin."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from crslab import __version__
from crslab.regress.transcript import sha256_of
from crslab.sim.api import SimRun
from crslab.sim.config import SimConfig
from crslab.sim.session import DEFAULT_DEADLINE_S, NO_LIMITS, Limits, RunResult, Simulation
from crslab.sim.sinks import MemorySink

NO_LAB_FUNCTION = "no-lab"
"""Status of a run whose lab file defines no ``lab()`` (it would not link on the board)."""


@dataclass
class LabRun:
    """A finished run (``SimRun``) and how long it simulated."""

    run: SimRun
    end_tick: int

    @property
    def status(self) -> str:
        """ok, crashed, exited, hung, nan, output-limit, or no-lab."""
        return self.run.result.status


def run_lab(config: SimConfig, end_tick: int, *, deadline_s: float = DEFAULT_DEADLINE_S,
            limits: Limits = NO_LIMITS) -> LabRun:
    """Run ``config`` to ``end_tick`` at full speed. Raises ``SimError`` when the worker cannot
    start; a lab without ``lab()`` gives status ``no-lab`` and no run."""
    memory = MemorySink()
    with Simulation(config, deadline_s=deadline_s, limits=limits) as sim:
        if not sim.symbols & 1:
            name = config.build.source.name
            result = RunResult(NO_LAB_FUNCTION, 0, f"{name} defines no lab() function")
        else:
            result = sim.run(end_tick, on_serial=memory.on_serial)
    return LabRun(SimRun(result=result, calls=memory.calls, log=None), end_tick)


def run_header(config: SimConfig, end_tick: int, scenario_arg: str | None) -> dict[str, str]:
    """The golden-file header fields that say what produced a transcript: crslab's version, the
    lab and scenario (names and content hashes) and the options that change what is printed."""
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
        "end_s": f"{end_tick / 1000:.3f}",
        "rest_motor_rad": " ".join(repr(float(v)) for v in config.rest_motor_rad),
        "startup_delay": "yes" if config.startup_ticks else "no",
    }
