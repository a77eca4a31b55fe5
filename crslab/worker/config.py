"""What a simulation run is told: everything that decides its transcript, and nothing else."""

from __future__ import annotations

from dataclasses import dataclass, field

from crslab.framework_facts import LAB_BUDGET_INSTRUCTIONS, STARTUP_TICKS
from crslab.lab.build import LabBuild
from crslab.plant.model_files import REST_MOTOR_RAD
from crslab.plant.plant_params import PlantParams
from crslab.scenario.load import Scenario
from crslab.world import FREE_AIR, World


@dataclass(frozen=True)
class HandGains:
    """The hand's bounded PID on the DH joints (N.m/rad, N.m/(rad.s), N.m.s/rad, N.m).

    The bound beats the framework's hold controller (5 units = 30 N.m on each motor, so up to
    60 N.m on joint 2) plus gravity, as a student's hands do.
    """

    kp: float = 3000.0
    ki: float = 30000.0
    kd: float = 40.0
    max_nm: float = 120.0


@dataclass(frozen=True)
class RunConfig:
    """One run: the lab, the scenario, and the options that change what it prints."""

    build: LabBuild
    scenario: Scenario
    rest_motor_rad: tuple[float, float, float] = REST_MOTOR_RAD
    startup_ticks: int = STARTUP_TICKS
    strict_nan: bool = False
    budget_instructions: int = LAB_BUDGET_INSTRUCTIONS
    """What one lab() call may cost before it is counted over budget: WebAssembly instructions (a
    time a native firmware's lab() takes is compared at one instruction per cycle of the 150 MHz F28335)."""
    log_signals: bool = False
    log_every_ticks: int = 1
    """The scope log keeps one row per tick divisible by this (1: every tick; crslab serve's page:
    every 5th, what the course's Simulink model samples, unless the run records a CSV or rrd)."""
    hand: HandGains = HandGains()
    sandboxed: bool = True  # compiled and run in crslab.sandbox (it never changes the transcript)
    motor_board: str | None = None
    """``none`` or ``piccolo`` (framework_facts.MOTOR_BOARDS); None: the lab's generation's."""
    plant: PlantParams = field(default_factory=PlantParams.defaults)
    """The simulated arm's motor gain, drive, friction and variations (``--plant FILE``)."""
    world: World = FREE_AIR
    """What the arm can touch (``--world NAME|FILE``): free air (``none``) unless a world is given."""

    @property
    def motor_board_model(self) -> str:
        """The motor board this run uses: the one asked for, else the generation's default."""
        return self.motor_board or self.build.generation.default_motor_board
