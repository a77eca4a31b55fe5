"""One run put together, in one place: every way of running a lab (``crslab sim`` and ``debug``,
``record``, ``check`` and ``grade``, ``sweep``, ``serve``'s page, the Python API, ``identify``,
``friction``, ``doctor``, ``contest``) goes through here.

- :func:`make_config`: the lab built (WebAssembly, or native), the scenario loaded and checked
  against it, the plant and the world: one run's :class:`~crslab.worker.config.RunConfig`.
  A caller that has built the lab already (serve's page shows the build before it runs) passes
  the build (``build=``), so it is not built twice.
- :func:`started`: the :class:`~crslab.run.board_run.BoardRun` started with its deadline and
  limits, and a lab that defines no ``lab()`` refused (:class:`NoLab`, one wording) before any
  tick.
- :func:`run_kept`: a started run taken to its end with every sink fed, its result returned with
  what it printed and logged (``calls``, ``sent``, ``log``).

>>> NoLab("lab1.c").status, str(NoLab("lab1.c"))
(<RunStatus.NO_LAB: 'no-lab'>, 'lab1.c defines no lab() function')
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from crslab.framework_facts import LAB_BUDGET_INSTRUCTIONS, MOTOR_BOARDS, STARTUP_TICKS
from crslab.lab.build import LabBuild, build_lab
from crslab.plant.model_files import REST_MOTOR_RAD
from crslab.plant.plant_params import PlantParams
from crslab.run.board_run import DEFAULT_DEADLINE_S, NO_LIMITS, BoardRun, Limits, RunError
from crslab.run.status import RunResult, RunStatus
from crslab.sandbox import resolve as resolve_sandbox
from crslab.scenario.load import Scenario, check_lab, load_scenario
from crslab.sinks.memory import MemorySink
from crslab.sinks.sink import FanOut, Sink
from crslab.worker.config import RunConfig
from crslab.worker.debug_setup import DebugSetup
from crslab.world import FREE_AIR, World, load_world

DEFAULT_REST_MOTOR_RAD = REST_MOTOR_RAD
IN_A_WORLD_SCENARIO = "hands_off"
"""The scenario of a run in a world with fixtures when none is named: nobody touches the arm."""

__all__ = ["DEFAULT_DEADLINE_S", "DEFAULT_REST_MOTOR_RAD", "NO_LIMITS", "Limits", "NoLab", "make_config",
           "run_kept", "started"]


class NoLab(RunError):
    """The lab file defines no ``lab()`` (the board would not link without one): refused before
    any tick, with status ``no-lab``."""

    def __init__(self, lab_name: str) -> None:
        super().__init__(f"{lab_name} defines no lab() function", RunStatus.NO_LAB)


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
    build: LabBuild | None = None,
) -> RunConfig:
    """Build the lab (cached) and load the scenario into one run's configuration.

    The scenario is ``scenario`` (a name, a file or a loaded one); None: the tour, or in a world
    with fixtures :data:`IN_A_WORLD_SCENARIO` (nobody touches the arm). The arm's true resting pose
    is ``rest_motor_rad``, else the scenario's, else the default.
    ``budget`` is what one lab() call may cost (WebAssembly instructions); ``native`` builds the
    lab with the host's compiler instead of as WebAssembly. ``sandbox``: True requires the sandbox,
    False turns it off, None (default) uses it when
    this machine has it (see :func:`crslab.sandbox.resolve`). ``motor_board`` is ``none`` or
    ``piccolo``; None takes the lab's generation's (Gen A: none, Gen B: piccolo). ``debug`` and
    ``break_when`` build the lab for a debugger (:func:`crslab.lab.build.build_lab`). ``plant`` is
    the arm's plant parameters or a plant file (``crslab identify`` writes one); None: crslab's arm.
    ``world`` is what the arm can touch: a :class:`~crslab.world.World`, a built-in world's
    name (``none``, ``contest``) or a world file; None: free air (``none``). ``build``: the lab
    already built (then ``lab`` and the build options are not used again).
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
    if scenario is None and not _free_air(world):
        scenario = IN_A_WORLD_SCENARIO  # the tour's hand would drag the arm through the fixtures
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    rest = tuple(float(v) for v in (rest_motor_rad or sc.rest_motor_rad or DEFAULT_REST_MOTOR_RAD))
    if world is None:
        world = FREE_AIR
    elif not isinstance(world, World):
        world = load_world(world, rest_motor_rad=rest)  # type: ignore[arg-type]
    sandboxed = resolve_sandbox(sandbox)
    if build is None:
        build = build_lab(Path(lab) if lab is not None else None, native=native, sanitize=sanitize,
                          sandboxed=sandboxed, debug=debug, break_when=break_when)
    check_lab(sc, build)
    return RunConfig(
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


def _free_air(world: World | str | Path | None) -> bool:
    """Whether ``world`` is free air (None, ``none``, or a world without fixtures).

    >>> _free_air(None), _free_air("none"), _free_air("contest")
    (True, True, False)
    """
    if isinstance(world, World):
        return world.is_free_air
    return world is None or str(world) == FREE_AIR.name


@contextmanager
def started(config: RunConfig, *, deadline_s: float | None = DEFAULT_DEADLINE_S, limits: Limits = NO_LIMITS,
            debug: DebugSetup | None = None,
            on_started: Callable[[], None] | None = None) -> Iterator[BoardRun]:
    """``config``'s lab started in its worker, ready to run (see
    :class:`~crslab.run.board_run.BoardRun` for ``deadline_s``, ``limits``, ``debug`` and
    ``on_started``); the worker is stopped when the block ends. Raises :class:`NoLab` when the lab
    defines no ``lab()``, ``RunError`` when the worker cannot start."""
    with BoardRun(config, deadline_s=deadline_s, limits=limits, debug=debug, on_started=on_started) as sim:
        if not sim.defines_lab:
            raise NoLab(config.build.source.name)
        yield sim


def run_kept(config: RunConfig, end_tick: int, sinks: Sequence[Sink] = (), *, speed: float | None = None,
             deadline_s: float | None = DEFAULT_DEADLINE_S, limits: Limits = NO_LIMITS) -> RunResult:
    """Run ``config`` to ``end_tick`` (``speed`` None: as fast as possible, else x real time),
    feeding ``sinks``, and return the result with every serial call, the print marks and the
    scope log (when ``config.log_signals``) kept. A lab without ``lab()`` ends ``no-lab`` before
    any tick; raises ``RunError`` when the worker cannot start."""
    memory = MemorySink()
    try:
        with started(config, deadline_s=deadline_s, limits=limits) as sim:
            result = sim.run(end_tick, FanOut([memory, *sinks]), speed=speed)
    except NoLab as exc:
        return RunResult(exc.status, 0, str(exc), lab_file=config.build.source)
    return dataclasses.replace(result, calls=memory.calls, sent=memory.sent,
                               log=memory.log if config.log_signals else None)
