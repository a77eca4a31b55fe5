"""One sample of a sweep as a job for an executor: the lab's source, the run's options and the
sample's values travel together; the job builds the lab where it runs, runs it with its scope log
kept, and returns one table row (:class:`Row`: plain values, small to send back).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from crslab.framework_facts import TICKS_PER_S
from crslab.lab.build import LabBuildError, LabForbidden
from crslab.lab.source import LabSource
from crslab.regress.compare import DEFAULT_ABS_TOL, DEFAULT_REL_TOL, compare
from crslab.regress.transcript import split_lines
from crslab.run.assemble import run_kept
from crslab.run.board_run import DEFAULT_DEADLINE_S, NO_LIMITS, Limits, RunError
from crslab.run.status import RunStatus
from crslab.sweep import variations
from crslab.sweep.run_metrics import METRIC_NAMES, run_metrics
from crslab.sweep.variations import Vary
from crslab.worker.config import RunConfig

Row = dict[str, object]
"""One table row: column name to value (int, float, bool or str)."""


@dataclass(frozen=True)
class SweepSpec:
    """What every sample of a sweep shares. ``config`` is the client's run configuration: its
    build is replaced by the one made where the job runs, from ``lab``."""

    lab: LabSource
    config: RunConfig
    end_tick: int
    varies: tuple[Vary, ...]
    seed: int = 1
    deadline_s: float = DEFAULT_DEADLINE_S
    limits: Limits = NO_LIMITS
    golden: bytes | None = None
    abs_tol: float = DEFAULT_ABS_TOL
    rel_tol: float = DEFAULT_REL_TOL

    def columns(self) -> list[str]:
        """The table's columns, in order."""
        golden = ["golden_match"] if self.golden is not None else []
        return [
            "sample",
            *(v.name for v in self.varies),
            "status",
            "passed",
            "end_s",
            *METRIC_NAMES,
            *golden,
            "message",
        ]

    def row(
        self,
        sample: int,
        values: tuple[float, ...],
        status: RunStatus,
        message: str = "",
        end_tick: int = 0,
        metrics: dict[str, float] | None = None,
        golden_match: bool | None = None,
    ) -> Row:
        """A row; ``passed`` when the run ended normally, never left the safety envelope, never
        had the motor board cut out, and (with a golden file) printed what it holds."""
        metrics = metrics if metrics is not None else {name: math.nan for name in METRIC_NAMES}
        passed = (
            status is RunStatus.OK
            and metrics["safety_trips"] == 0
            and metrics["motor_board_cutouts"] == 0
            and golden_match is not False
        )
        row: Row = {
            "sample": sample,
            **{v.name: x for v, x in zip(self.varies, values, strict=True)},
            "status": str(status),
            "passed": bool(passed),
            "end_s": end_tick / TICKS_PER_S,
            **metrics,
        }
        if self.golden is not None:
            row["golden_match"] = bool(golden_match)
        row["message"] = message.splitlines()[0] if message else ""
        return row


@dataclass(frozen=True)
class SweepJob:
    """Sample ``sample`` of a sweep, at ``values`` (one per varied quantity)."""

    spec: SweepSpec
    sample: int
    values: tuple[float, ...]

    @property
    def name(self) -> str:
        return f"sample {self.sample}"

    def lost(self, status: RunStatus, message: str, elapsed_s: float = 0.0) -> Row:
        return self.spec.row(self.sample, self.values, status, message)

    def run(self) -> Row:
        spec = self.spec
        try:
            with spec.lab.private_build(
                native=spec.config.build.native, sanitize=spec.config.build.sanitized,
                sandboxed=spec.config.sandboxed
            ) as build:
                config = variations.apply(
                    dataclasses.replace(spec.config, build=build, log_signals=True),
                    spec.varies,
                    self.values,
                    seed=spec.seed,
                    sample=self.sample,
                )
                result = run_kept(config, spec.end_tick, deadline_s=spec.deadline_s, limits=spec.limits)
        except LabForbidden as exc:
            return self.lost(RunStatus.FORBIDDEN, str(exc))
        except LabBuildError as exc:
            return self.lost(RunStatus.BUILD_ERROR, str(exc))
        except RunError as exc:
            return self.lost(exc.status, str(exc))
        if result.status is RunStatus.NO_LAB:
            return self.lost(result.status, result.message)
        metrics = run_metrics(result.log, result.stats, startup_ticks=config.startup_ticks)
        matched = None
        if spec.golden is not None:
            matched = (
                result.ok
                and compare(
                    split_lines(spec.golden),
                    split_lines(result.transcript, result.calls),
                    abs_tol=spec.abs_tol,
                    rel_tol=spec.rel_tol,
                ).ok
            )
        return spec.row(
            self.sample, self.values, result.status, result.message, result.end_tick, metrics, matched
        )
