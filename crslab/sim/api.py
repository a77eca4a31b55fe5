"""Run a lab from Python: ``simulate(lab, scenario, ...)`` returns its transcript and signals.

>>> run = simulate(duration_s=5.0)          # the default Lab 1 on the tour, first 5 s
>>> run.status, run.transcript.count(b"\\n\\r")
(<RunStatus.OK: 'ok'>, 6)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

from crslab.framework_facts import LAB_BUDGET_INSTRUCTIONS, MOTOR_BOARDS, STARTUP_TICKS
from crslab.lab.build import build_lab
from crslab.plant.model_files import REST_MOTOR_RAD
from crslab.plant.plant_params import PlantParams
from crslab.sandbox import resolve as resolve_sandbox
from crslab.scenario.event import seconds_to_tick
from crslab.scenario.load import Scenario, check_lab, load_scenario
from crslab.sim.session import DEFAULT_DEADLINE_S, NO_LIMITS, Limits, Simulation
from crslab.sim.status import RunResult
from crslab.sinks.memory import MemorySink
from crslab.sinks.sink import FanOut, Sink
from crslab.worker.config import SimConfig
from crslab.world.layout import FREE_AIR, World, load_world

DEFAULT_REST_MOTOR_RAD = REST_MOTOR_RAD


def make_config(
    lab: str | Path | None = None,
    scenario: str | Scenario | None = None,
    *,
    startup_delay: bool = True,
    rest_motor_rad: Sequence[float] | None = None,
    log: bool = False,
    strict: bool = False,
    budget: int = LAB_BUDGET_INSTRUCTIONS,
    native: bool = False,
    sanitize: bool = False,
    sandbox: bool | None = None,
    motor_board: str | None = None,
    debug: bool = False,
    break_when: str | None = None,
    plant: PlantParams | str | Path | None = None,
    world: World | str | Path | None = None,
) -> SimConfig:
    """Build the lab (cached) and load the scenario into one run's configuration.

    The arm's true resting pose is ``rest_motor_rad``, else the scenario's, else the default.
    ``budget`` is what one lab() call may cost (WebAssembly instructions); ``native`` builds the
    lab with the host's compiler instead of as WebAssembly. ``sandbox``: True requires the sandbox,
    False turns it off, None (default) uses it when
    this machine has it (see :func:`crslab.sandbox.resolve`). ``motor_board`` is ``none`` or
    ``piccolo``; None takes the lab's generation's (Gen A: none, Gen B: piccolo). ``debug`` and
    ``break_when`` build the lab for a debugger (:func:`crslab.lab.build.build_lab`). ``plant`` is
    the arm's plant parameters or a plant file (``crslab identify`` writes one); None: crslab's arm.
    ``world`` is what the arm can touch: a :class:`~crslab.world.layout.World`, a built-in world's
    name (``none``, ``contest``) or a world file; None: free air (``none``).
    Raises ``ScenarioError`` when the scenario writes a variable the lab does not watch,
    ``ValueError`` for an unknown motor board, ``PlantParamsError`` for a bad plant file,
    ``WorldError`` (one line: file, line, key) for a bad world.
    """
    if motor_board is not None and motor_board not in MOTOR_BOARDS:
        raise ValueError(f"no motor board {motor_board!r}; choose one of {', '.join(MOTOR_BOARDS)}")
    if plant is None:
        plant = PlantParams.defaults()
    elif not isinstance(plant, PlantParams):
        plant = PlantParams.load(plant)
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    rest = tuple(float(v) for v in (rest_motor_rad or sc.rest_motor_rad or DEFAULT_REST_MOTOR_RAD))
    if world is None:
        world = FREE_AIR
    elif not isinstance(world, World):
        world = load_world(world, rest_motor_rad=rest)  # type: ignore[arg-type]
    sandboxed = resolve_sandbox(sandbox)
    build = build_lab(Path(lab) if lab is not None else None, native=native, sanitize=sanitize,
                      sandboxed=sandboxed, debug=debug, break_when=break_when)
    check_lab(sc, build)
    return SimConfig(
        build=build,
        scenario=sc,
        rest_motor_rad=rest,  # type: ignore[arg-type]
        startup_ticks=STARTUP_TICKS if startup_delay else 0,
        strict_nan=strict,
        budget_instructions=int(budget),
        log_signals=log,
        sandboxed=sandboxed,
        motor_board=motor_board,
        plant=plant,
        world=world,
    )


def simulate(
    lab: str | Path | None = None,
    scenario: str | Scenario | None = None,
    *,
    duration_s: float | None = None,
    speed: float | None = None,
    deadline_s: float = DEFAULT_DEADLINE_S,
    limits: Limits = NO_LIMITS,
    sinks: Sequence[Sink] = (),
    **options: object,
) -> RunResult:
    """Run ``lab`` (default: crslab's Lab 1) on ``scenario`` (default: the tour).

    ``duration_s`` (simulated) overrides the scenario's end; ``speed`` None runs as fast as
    possible. Other keyword options go to :func:`make_config`.
    """
    config = make_config(lab, scenario, **options)  # type: ignore[arg-type]
    end_tick = seconds_to_tick(duration_s) if duration_s is not None else config.scenario.end_tick
    memory = MemorySink()
    with Simulation(config, deadline_s=deadline_s, limits=limits) as sim:
        result = sim.run(end_tick, FanOut([memory, *sinks]), speed=speed)
    return dataclasses.replace(result, calls=memory.calls, sent=memory.sent, log=memory.log)
