"""pytest plugin: check what a lab prints against a golden file, in a student's own repository.

Installed with crslab (a ``pytest11`` entry point), so any test can ask for the
``crslab_check`` fixture. This lab, this scenario, this golden file::

    def test_lab1_prints_the_tour(crslab_check):
        crslab_check("lab1.c", scenario="tour", golden="golden/lab1_tour.txt")

Paths are relative to the test file's folder (a scenario is a built-in name or a TOML file).
The run is compared number-aware, as ``crslab check`` does (``abs_tol``, ``rel_tol``); a
mismatch fails the test with the report naming the first differing lines, their simulated
time and the numbers that differ. A lab that crashes or hangs fails it too, and so does a failed
expectation of the scenario (``kind = "expect"``), with one line per failure.

To write the golden files, record once with ``pytest --crslab-record`` (it rewrites every golden
file the tests name, with a header naming the lab, the scenario and crslab's version) and commit
them. A golden file written by ``crslab record`` works as well. What a test leaves out (scenario,
duration, resting pose, startup delay) is the golden file's, read exactly as ``crslab check``
reads it (:func:`crslab.regress.transcript.recorded_run`).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest


def pytest_addoption(parser: pytest.Parser) -> None:
    """``--crslab-record``: write the golden files instead of checking against them."""
    group = parser.getgroup("crslab")
    group.addoption("--crslab-record", action="store_true", default=False,
                    help="crslab_check: run each lab and (re)write its golden file instead of comparing")


class CrslabCheckFailed(AssertionError):
    """The lab's transcript does not match its golden file (or the lab did not run)."""


def check_against_golden(lab: str | Path, *, golden: str | Path, scenario: str | None = None,
                         base: Path | None = None, record: bool = False, abs_tol: float | None = None,
                         rel_tol: float | None = None, duration_s: float | None = None,
                         rest_motor_rad: tuple[float, float, float] | None = None,
                         startup_delay: bool | None = None, deadline_s: float | None = None,
                         plant: str | Path | None = None, world: str | Path | None = None) -> str:
    """Run ``lab`` on ``scenario`` and compare with (or, with ``record``, write) ``golden``.

    Options left as None are the golden file's when checking (the defaults when recording).
    Returns the one-line verdict; raises :class:`CrslabCheckFailed` with the full report when the
    transcript differs or the lab does not run, ``FileNotFoundError`` for a missing golden and
    ``GoldenError`` for a malformed one.
    """
    from crslab.regress.compare import DEFAULT_ABS_TOL, DEFAULT_REL_TOL, compare
    from crslab.regress.runner import run_header
    from crslab.regress.transcript import (
        RecordedRun,
        find_scenario,
        read_golden,
        recorded_run,
        split_lines,
        write_golden,
    )
    from crslab.run.api import make_config
    from crslab.run.assemble import run_kept
    from crslab.run.board_run import DEFAULT_DEADLINE_S
    from crslab.scenario.event import seconds_to_tick

    base = base or Path.cwd()
    lab_path = base / lab
    golden_path = base / golden
    recorded = RecordedRun()
    if not record:
        if not golden_path.is_file():
            raise FileNotFoundError(f"{golden_path}: no golden file yet; record it with "
                                    "'pytest --crslab-record' and commit it")
        gold = read_golden(golden_path)
        recorded = recorded_run(gold, [base])
    given = find_scenario(scenario, [base]) if scenario is not None else None
    given_plant = find_scenario(str(plant), [base]) if plant is not None else None
    given_world = find_scenario(str(world), [base]) if world is not None else None
    options = recorded.overridden(scenario=given, duration_s=duration_s, rest_motor_rad=rest_motor_rad,
                                  startup_delay=startup_delay, plant=given_plant, world=given_world)
    config = make_config(lab_path, options.scenario, startup_delay=options.startup_delay is not False,
                         rest_motor_rad=options.rest_motor_rad, motor_board=options.motor_board,
                         plant=options.plant, world=options.world)
    end_tick = config.scenario.end_tick if options.duration_s is None else seconds_to_tick(options.duration_s)
    result = run_kept(config, end_tick, deadline_s=deadline_s or DEFAULT_DEADLINE_S)
    if not result.ok:  # a crash, a hang, a failed expectation of the scenario: never recorded
        raise CrslabCheckFailed(f"{lab_path.name} on {config.scenario.name}: {result.diagnosis()}")
    if record:
        golden_path.parent.mkdir(parents=True, exist_ok=True)
        header = run_header(config, end_tick, scenario, plant, world)
        write_golden(golden_path, header, result.transcript)
        return f"recorded {golden_path}"
    comparison = compare(split_lines(gold.body), split_lines(result.transcript, result.calls),
                         abs_tol=DEFAULT_ABS_TOL if abs_tol is None else abs_tol,
                         rel_tol=DEFAULT_REL_TOL if rel_tol is None else rel_tol)
    if not comparison.ok:
        raise CrslabCheckFailed(f"{lab_path.name} on {config.scenario.name} against {golden_path.name}: "
                                + comparison.report(max_lines=5))
    return comparison.headline()


@pytest.fixture
def crslab_check(request: pytest.FixtureRequest) -> Callable[..., str]:
    """``crslab_check(lab, scenario=None, golden=..., **options)``: run the lab on the scenario and
    fail the test unless it prints what the golden file holds (see the module's docs). Options:
    ``abs_tol``, ``rel_tol``, ``duration_s``, ``rest_motor_rad``, ``startup_delay``, ``deadline_s``,
    ``plant`` (a plant file, relative to the test file), ``world`` (a built-in world's name or a world
    file, relative to the test file)."""
    base = Path(str(request.path)).parent
    record = bool(request.config.getoption("crslab_record", default=False))

    def check(lab: str | Path, scenario: str | None = None, *, golden: str | Path, **options: object) -> str:
        from crslab.lab.build import LabBuildError
        from crslab.plant.plant_params import PlantParamsError
        from crslab.regress.transcript import GoldenError
        from crslab.scenario.load import ScenarioError
        from crslab.world import WorldError

        try:
            return check_against_golden(lab, golden=golden, scenario=scenario, base=base, record=record,
                             **options)  # type: ignore[arg-type]
        except (CrslabCheckFailed, FileNotFoundError, ScenarioError, GoldenError, PlantParamsError,
                WorldError) as exc:
            failure = str(exc)
        except LabBuildError as exc:  # a bad lab file: the compiler's words, not a traceback
            failure = f"{exc}\n{exc.diagnostics}".rstrip()
        pytest.fail(failure, pytrace=False)

    return check
