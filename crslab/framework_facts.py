"""The course framework's numbers for Python, read from the one header that holds them
(``csrc/port/framework_facts.h``, compiled into the C core: :data:`crslab._bindings.constants`): the
emulated board is built from the same header, so no number of the framework is written twice.
What differs between the framework's generations is in their rows (:mod:`crslab.generations`).

>>> STARTUP_TICKS, CLAMP_UNITS, HOLD_REANCHOR_RAD, SERIAL_CHARS_PER_MS
(4100, 5.0, 0.15, 11.52)
"""

from __future__ import annotations

from crslab._bindings import constants as c

TICKS_PER_S: int = c.CRS_TICKS_PER_S
"""The framework's tick: one a millisecond (tick k is at t = k / TICKS_PER_S s)."""
STARTUP_TICKS: int = c.CRS_STARTUP_TICKS
"""The first lab() call is at 4.1 s (the brake releases at 4.0 s)."""
CLAMP_UNITS: float = c.CRS_CLAMP_UNITS
"""Every command is clamped to +-5 command units."""
HOLD_KP_FAR: float = c.CRS_HOLD_KP_FAR
HOLD_KP_NEAR: float = c.CRS_HOLD_KP_NEAR
HOLD_KP_SWITCH_RAD: float = c.CRS_HOLD_KP_SWITCH_RAD
HOLD_KD: float = c.CRS_HOLD_KD
HOLD_REANCHOR_RAD: float = c.CRS_HOLD_REANCHOR_RAD
"""The hold controller: Kp 15 beyond 0.1 rad of error, else 25; Kd 1; references re-anchored
when more than 0.15 rad from the arm outside the envelope."""
WRIST_ESTOP_RAD: float = c.CRS_WRIST_ESTOP_RAD
"""A wrist turned farther than this latches every output to zero."""
ENCODER_COUNTS_PER_REV: int = c.CRS_ENCODER_COUNTS_PER_REV

MB_COUNTS_PER_UNIT: int = c.CRS_MB_COUNTS_PER_UNIT
MB_LIMIT_UNITS: float = c.CRS_MB_LIMIT_COUNTS / c.CRS_MB_COUNTS_PER_UNIT
"""The motor board cuts out when one joint is commanded beyond this ..."""
MB_OVER_LIMIT_MS: int = c.CRS_MB_OVER_LIMIT_TICKS
"""... for this many consecutive ms."""
MB_TIMEOUT_MS: int = c.CRS_MB_TIMEOUT_TICKS
"""No command for this many ms also cuts every output."""
MOTOR_BOARDS: dict[str, int] = {"none": c.CRS_MOTOR_BOARD_NONE, "piccolo": c.CRS_MOTOR_BOARD_PICCOLO}
"""The motor-board models by name (``--motor-board``)."""

SERIAL_BAUD: int = c.CRS_SERIAL_BAUD
SERIAL_CHARS_PER_MS: float = c.CRS_SERIAL_BAUD / c.CRS_SERIAL_BITS_PER_CHAR / c.CRS_TICKS_PER_S
SCI_TX_FIFO_CHARS: int = c.CRS_SCI_TX_FIFO
SCI_TX_SHIFT_CHARS: int = c.CRS_SCI_TX_SHIFT
LEDS_AT_START: int = c.CRS_LEDS_AT_START
"""Bit 0: GPIO34, bit 1: GPIO60; both start high."""

MATLAB_START: int = c.CRS_MATLAB_START
"""'*': every MATLAB message and reply starts with it."""
SIMULINK_INPUTS: int = c.CRS_SIMULINK_INPUTS
"""Simulink sends seven int16 values (SIMU_Var1..7_fromSIMU_16bit)."""
SIMULINK_PLOTS: int = c.CRS_SIMULINK_PLOTS
"""... and receives four (Simulink_PlotVar1..4) ..."""
SIMULINK_SCALE: int = c.CRS_SIMULINK_SCALE
"""... each as int32(10000 * value)."""
SIMULINK_PERIOD_MS: int = c.CRS_SIMULINK_PERIOD_MS
"""The course's Simulink model exchanges a packet every 5 ms."""
SIMULINK_SYNC = bytes([c.CRS_SIMULINK_SYNC_1, c.CRS_SIMULINK_SYNC_2])
"""A Simulink packet starts FF 7F."""

DATA_RAM_START: int = c.CRS_DATA_RAM_START
"""The first word of the F28335's data memory the course's linker gives a lab (L1)."""
DATA_RAM_END: int = c.CRS_DATA_RAM_END
"""One past its last word (the end of L7)."""
LAB_BUDGET_INSTRUCTIONS: int = c.CRS_LAB_BUDGET_INSTRUCTIONS
"""What one lab() call may cost by default, in WebAssembly instructions (half of a tick's cycles)."""
CPU_CYCLES_PER_TICK: int = c.CRS_CPU_CYCLES_PER_TICK
"""The F28335's cycles in one 1 ms tick (150 MHz)."""
