/* The motor board between the framework's commands and the amplifiers (docs/framework.md section 5).
 * Internal to the board; not read by cffi (its state, crs_motor_board, is in board.h).
 *
 * Piccolo: each command arrives as whole PWM counts (CRS_MB_COUNTS_PER_UNIT per command unit,
 * truncated toward zero as the DSP converts it); a message with a joint beyond
 * CRS_MB_REJECT_COUNTS is rejected (as if none arrived). A joint commanded beyond
 * CRS_MB_LIMIT_COUNTS for CRS_MB_OVER_LIMIT_TICKS consecutive ms cuts every output from the next
 * such command on, until that joint's command is back within the limit; CRS_MB_TIMEOUT_TICKS ms
 * without a command cut every output until one arrives. Between commands the outputs hold.
 * None: the command passes through unchanged. */
#ifndef CRSLAB_MOTOR_BOARD_H
#define CRSLAB_MOTOR_BOARD_H

#include <stdint.h>

#include "board.h"

/* Zero the state. */
void crs_motor_board_init(crs_motor_board *mb);

/* One ms of the motor board `model` (CRS_MOTOR_BOARD_*, what the run is configured with):
 * `command_units` is what the framework sent (NULL: nothing arrived this ms). Updates
 * mb->out_units, mb->off and, when a cut-out starts or ends, records an event at `tick`;
 * returns 1 when the event list is full (the reader should take it), else 0. */
int crs_motor_board_step(int32_t model, crs_motor_board *mb, int64_t tick, const double *command_units);

#endif
